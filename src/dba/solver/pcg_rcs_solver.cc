// The RCS solved by PCG; see pcg_rcs_solver.h.
#include "dba/solver/pcg_rcs_solver.h"

#include <stdexcept>
#include <utility>

#include "dba/solver/block_jacobi.h"
#include "dba/solver/two_level_preconditioner.h"

namespace dba {

PcgRcsSolver::PcgRcsSolver(const BsmcMatrix& S, const LinearSolverOptions& options)
    : options_(options.pcg),
      multiplier_(S, options.pcg.num_threads, options.pcg.product_precision()) {
  if (options.preconditioner == PreconditionerType::kTwoLevel) {
    preconditioner_ = std::make_unique<TwoLevelPreconditioner>(
        S, options.coarse_aggregate_size, options.pcg.num_threads, options.coarse_row_bases,
        options.aggregation_order);
  } else {
    preconditioner_ = std::make_unique<BlockJacobiPreconditioner>(S, options.pcg.num_threads);
  }
  scratch_.Resize(S.num_rows());
}

int64_t PcgRcsSolver::MemoryBytes() const {
  return preconditioner_->MemoryBytes() + scratch_.vectors.size() * 8 + multiplier_.MemoryBytes();
}

int64_t PcgSolveDoubles(const BsmcMatrix& S, ProductPrecision precision) {
  int64_t diagonal = 0;  // values of the diagonal blocks
  for (int32_t i = 0; i < S.num_block_rows(); ++i) {
    diagonal += int64_t{S.block_size(i)} * S.block_size(i);
  }
  // The block-Jacobi inverse, for a mixed product the diagonal in double,
  // PCG's vectors.
  const int64_t copies = precision == ProductPrecision::kMixed ? 2 : 1;
  return copies * diagonal + kPcgVectors * S.num_rows();
}

int64_t PcgPathBytes(const BsmcMatrix& S, ProductPrecision precision) {
  return S.ValueBytes() + S.StructureBytes() + (PcgSolveDoubles(S, precision) + S.num_rows()) * 8;
}

LinearSolveSummary PcgRcsSolver::Solve(BsmcMatrix& S, const double* b, double* x) {
  if (&S != &multiplier_.matrix()) {
    throw std::logic_error("PcgRcsSolver: Solve on a matrix other than the one given at construction");
  }
  if (S.values_narrowed()) {
    throw std::logic_error("PcgRcsSolver: Solve on narrowed values (S must be re-formed first)");
  }
  PlaceSolveStorage(std::exchange(lent_, nullptr), preconditioner_.get(), &multiplier_, &scratch_,
                    S.num_rows());
  preconditioner_->Update(S);
  if (multiplier_.precision() == ProductPrecision::kMixed) multiplier_.Narrow(&S);
  const PcgSummary pcg = SolvePcg(multiplier_, *preconditioner_, b, x, options_, &scratch_);
  ReturnSolvePages(preconditioner_.get(), &multiplier_, &scratch_);
  return ToLinearSolveSummary(pcg);
}

int64_t PcgRcsSolver::PerSolveDoubles() const {
  // What PlaceSolveStorage lays out.
  return preconditioner_->NumericDoubles() + multiplier_.DiagonalDoubles() +
         kPcgVectors * multiplier_.num_rows();
}

void PlaceSolveStorage(double* place, Preconditioner* preconditioner,
                       SymmetricMultiplier* multiplier, PcgScratch* scratch, int64_t num_rows) {
  const int64_t numeric = preconditioner->NumericDoubles();
  const int64_t diagonal = multiplier->DiagonalDoubles();
  preconditioner->PlaceNumeric(place);
  multiplier->PlaceDiagonal(place == nullptr ? nullptr : place + numeric);
  scratch->Resize(num_rows);
  scratch->vectors.Place(place == nullptr ? nullptr : place + numeric + diagonal);
}

void ReturnSolvePages(Preconditioner* preconditioner, SymmetricMultiplier* multiplier,
                      PcgScratch* scratch) {
  preconditioner->ReturnNumericPages();
  multiplier->ReturnDiagonalPages();
  scratch->ReturnPages();
}

LinearSolveSummary ToLinearSolveSummary(const PcgSummary& pcg) {
  LinearSolveSummary summary;
  summary.iterations = pcg.iterations;
  summary.relative_residual = pcg.relative_residual;
  summary.stop = PcgStopName(pcg.stop);
  return summary;
}

}  // namespace dba
