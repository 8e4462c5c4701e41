// The linear step of an LM iteration, (S + λ D_c) δc = b (paper eq. 1 and 4),
// solved where S lives. The LM loop asks its workers for one per solve
// (PointWorkers::MakeDampedRcsSolver, the symbolic phase of the linear
// solve) and calls Solve once per iteration, after FormRcs.
//
//   LocalDampedRcsSolver   the RcsSystem that FormRcs returned holds all of
//                          S: damped in place and solved by the solver of
//                          solver/rcs_solver.h (one process, or the main
//                          rank of a gathered RCS)
//   (cluster/mpi_point_workers.h) S spread over the ranks: every rank damps
//                          its rows and PCG runs across them
//
// Thread safety: one Solve at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "dba/common/memory.h"
#include "dba/rcs/form_rcs.h"
#include "dba/solver/rcs_solver.h"

namespace dba {

class DampedRcsSolver {
 public:
  virtual ~DampedRcsSolver() = default;
  // δc (num_unknowns of the system's layout) for the system of the last
  // FormRcs; `system` is that system, whose S may be damped and narrowed
  // in place.
  virtual LinearSolveSummary Solve(double lambda, const DampingBounds& bounds,
                                   RcsSystem* system, double* delta_c) = 0;
  // Bytes held beyond the RCS itself.
  virtual int64_t MemoryBytes() const = 0;
  // The least λ its solves are reliable at (RcsSolver::min_lambda).
  virtual double min_lambda() const = 0;
  // RcsSolver::DropDampingFloor, for the solves to come.
  virtual bool DropDampingFloor() = 0;
};

class LocalDampedRcsSolver : public DampedRcsSolver {
 public:
  // The solver for `S`'s structure (options.type, or auto's choice, written
  // to `choice`). `idle`: a buffer of `idle_doubles` that nothing reads
  // during a Solve (the candidate points', lm/local_point_workers.h) or
  // nullptr; where what the solver computes afresh each solve fits in it,
  // each Solve borrows it for that (borrows_idle()), resizing it if it is
  // smaller (its contents are lost).
  LocalDampedRcsSolver(const BsmcMatrix& S, const LinearSolverOptions& options,
                       RcsSolverChoice* choice, std::vector<double>* idle = nullptr,
                       int64_t idle_doubles = 0)
      : solver_(MakeRcsSolver(S, options, choice)), idle_(idle), idle_doubles_(idle_doubles) {
    const int64_t need = solver_->PerSolveDoubles();
    if (idle_ == nullptr || need == 0 || need > idle_doubles_) idle_ = nullptr;
  }
  LinearSolveSummary Solve(double lambda, const DampingBounds& bounds, RcsSystem* system,
                           double* delta_c) override {
    DampCameraBlocks(lambda, bounds, system->camera_side_jtj_diagonal, &system->S);
    if (idle_ != nullptr) {
      if (static_cast<int64_t>(idle_->size()) < idle_doubles_) {
        AssignZeros(idle_, static_cast<size_t>(idle_doubles_));
      }
      solver_->LendForNextSolve(idle_->data());
    }
    return solver_->Solve(system->S, system->b.data(), delta_c);
  }
  // Beyond the RCS and the idle buffer.
  int64_t MemoryBytes() const override {
    return solver_->MemoryBytes() - (idle_ != nullptr ? solver_->PerSolveDoubles() * 8 : 0);
  }
  double min_lambda() const override { return solver_->min_lambda(); }
  bool DropDampingFloor() override { return solver_->DropDampingFloor(); }
  // True if the solves borrow the idle buffer.
  bool borrows_idle() const { return idle_ != nullptr; }

 private:
  std::unique_ptr<RcsSolver> solver_;
  std::vector<double>* idle_;
  int64_t idle_doubles_;
};

}  // namespace dba
