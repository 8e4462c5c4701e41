// The RCS solved by truncated-Newton PCG (solver/pcg.h) with a block-Jacobi
// or two-level preconditioner. The multiplier's thread split, the preconditioner's storage
// and the PCG vectors are set up once, at construction; each Solve refreshes
// the preconditioner from S's values, narrows S for a mixed-precision
// product (PcgOptions::precision) and runs PCG from zero.
//
// Thread safety: one Solve at a time.
#pragma once

#include <memory>

#include "dba/bsmc/symmetric_multiply.h"
#include "dba/solver/pcg.h"
#include "dba/solver/rcs_solver.h"

namespace dba {

class PcgRcsSolver : public RcsSolver {
 public:
  // S must outlive the solver and keep its structure.
  PcgRcsSolver(const BsmcMatrix& S, const LinearSolverOptions& options);
  LinearSolveSummary Solve(BsmcMatrix& S, const double* b, double* x) override;
  LinearSolverType type() const override { return LinearSolverType::kPcg; }
  int64_t MemoryBytes() const override;
  double min_lambda() const override { return MinLambda(multiplier_.precision()); }
  bool DropDampingFloor() override { return dba::DropDampingFloor(options_.precision, &multiplier_); }
  int64_t PerSolveDoubles() const override;
  void LendForNextSolve(double* place) override { lent_ = place; }

 private:
  PcgOptions options_;
  SymmetricMultiplier multiplier_;
  std::unique_ptr<Preconditioner> preconditioner_;
  PcgScratch scratch_;
  double* lent_ = nullptr;  // for the next Solve
};

// The storage a PCG solve computes afresh each time (the preconditioner's
// values, a mixed product's diagonal copy, the vectors). PlaceSolveStorage
// puts it at `place` (lent for the solve), or
// with nullptr in their own storage; after a solve, ReturnSolvePages gives
// the pages of their own storage back to the system until the next solve,
// so that it is not held while the next RCS is formed.
// Its size in doubles from S's structure, before a solver exists: the
// inverses of the diagonal blocks, the copy, the vectors (a two-level
// preconditioner's coarse matrix, at 1M 6.4 doubles per camera against
// 81 for the inverses, is not counted: its size needs the aggregation).
int64_t PcgSolveDoubles(const BsmcMatrix& S, ProductPrecision precision);
void PlaceSolveStorage(double* place, Preconditioner* preconditioner,
                       SymmetricMultiplier* multiplier, PcgScratch* scratch, int64_t num_rows);
void ReturnSolvePages(Preconditioner* preconditioner, SymmetricMultiplier* multiplier,
                      PcgScratch* scratch);

// PCG's summary as the RCS solvers report it.
LinearSolveSummary ToLinearSolveSummary(const PcgSummary& pcg);

// Bytes of the PCG path for S: S itself, the preconditioner, the vectors,
// and for a mixed-precision product the diagonal blocks in double.
int64_t PcgPathBytes(const BsmcMatrix& S, ProductPrecision precision);

}  // namespace dba
