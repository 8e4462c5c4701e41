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
  // to `choice`).
  LocalDampedRcsSolver(const BsmcMatrix& S, const LinearSolverOptions& options,
                       RcsSolverChoice* choice)
      : solver_(MakeRcsSolver(S, options, choice)) {}
  LinearSolveSummary Solve(double lambda, const DampingBounds& bounds, RcsSystem* system,
                           double* delta_c) override {
    DampCameraBlocks(lambda, bounds, system->camera_side_jtj_diagonal, &system->S);
    return solver_->Solve(system->S, system->b.data(), delta_c);
  }
  int64_t MemoryBytes() const override { return solver_->MemoryBytes(); }
  double min_lambda() const override { return solver_->min_lambda(); }
  bool DropDampingFloor() override { return solver_->DropDampingFloor(); }

 private:
  std::unique_ptr<RcsSolver> solver_;
};

}  // namespace dba
