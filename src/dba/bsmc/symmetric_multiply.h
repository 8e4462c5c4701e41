// Symmetric matrix-vector product y = S x for S in BSMC (upper triangle
// stored), paper section 6.2: each stored block S_ij is read once and applied
// twice, y_i += S_ij x_j and (i != j) y_j += S_ijᵀ x_i.
//
// Threads: block rows are split into contiguous ranges of about equal value
// count, one per thread. A thread writes y_i for its own rows directly; the
// transposed products land in rows j > i that may belong to a later thread, so
// they go to the thread's spill buffer, which covers only the rows from the end
// of its range to the largest column it touches. The buffers are sized once,
// at construction (symbolic phase), and summed into y after a barrier. No
// atomics, no locks, no full-length scratch per call; the sum order is fixed,
// so the result does not depend on scheduling.
//
// Mixed precision: the product streams S from memory (2 flops per 8 bytes),
// so its time is S's size over the bandwidth. With ProductPrecision::kMixed,
// Narrow(&S) rewrites S's off-diagonal blocks as float32, in place, over the
// front of S's own value buffer, and keeps the diagonal blocks (which carry
// the LM damping) in double beside it: the product reads about half the
// bytes, accumulates in double, and is exact to float's 6e-8 per value.
// S's double values are gone until S is re-formed (BsmcMatrix::SetZero).
// (Packing each row's floats into the front of its own space instead, with
// the diagonal left in place and no copy, leaves a gap per row: the product
// measured 2.5x slower on s10k than with the floats packed contiguously.)
//
// Thread safety: one Multiply at a time per SymmetricMultiplier (it owns the
// spill buffers); the matrix is only read, except by Narrow.
#pragma once

#include <cstdint>
#include <vector>

#include "dba/bsmc/bsmc_matrix.h"
#include "dba/common/placed_doubles.h"

namespace dba {

enum class ProductPrecision { kDouble, kMixed };

class SymmetricMultiplier {
 public:
  // Splits the rows of `matrix`'s structure for `num_threads` threads. The
  // multiplier keeps a reference: the matrix must outlive it and its structure
  // must not change (values may).
  SymmetricMultiplier(const BsmcMatrix& matrix, int num_threads,
                      ProductPrecision precision = ProductPrecision::kDouble);

  // kMixed: narrows S's current values (see above); S must be the matrix
  // given at construction. Call after each change of S's values, before
  // Multiply. S's values are not valid afterwards, until SetZero.
  void Narrow(BsmcMatrix* S);

  // kMixed: the diagonal copy, DiagonalDoubles() doubles that each Narrow
  // writes: placed where the caller lends them until the product's last use
  // (PlaceDiagonal; nullptr: storage of its own again), else in storage of
  // its own, whose pages go back to the system until the next Narrow
  // (ReturnDiagonalPages, between solves).
  int64_t DiagonalDoubles() const { return diagonal_.size(); }
  void PlaceDiagonal(double* place) { diagonal_.Place(place); }
  void ReturnDiagonalPages();

  // From now on a double product (kDouble, no Narrow): for solves at a
  // damping below float's rounding (solver/pcg.h, MinLambda). Between
  // solves; narrowed values are to be re-formed before the next Multiply.
  void UseDoublePrecision();

  // y = S x; x and y have matrix.num_rows() entries and must not alias.
  void Multiply(const double* x, double* y) const;

  int num_threads() const { return static_cast<int>(row_split_.size()) - 1; }
  int64_t num_rows() const { return matrix_.num_rows(); }
  const BsmcMatrix& matrix() const { return matrix_; }
  ProductPrecision precision() const { return precision_; }
  // Bytes the multiplier holds: spill buffers, and for kMixed the diagonal
  // blocks in double.
  int64_t MemoryBytes() const;

 private:
  void PlanNarrowing();
  template <class Values>
  void MultiplyWith(const Values& values, const double* x, double* y) const;

  const BsmcMatrix& matrix_;
  ProductPrecision precision_;
  // kMixed: the diagonal blocks in double (row i's at diagonal_offset_[i]),
  // and the rounds of the in-place narrowing (rows [round_[k], round_[k+1])).
  std::vector<int64_t> diagonal_offset_;
  PlacedDoubles diagonal_;
  std::vector<int32_t> round_;
  std::vector<int32_t> row_split_;          // thread t owns [row_split_[t], row_split_[t+1])
  std::vector<int64_t> spill_begin_;        // scalar row where thread t's spill starts
  mutable std::vector<std::vector<double>> spill_;
};

// Reference: serial y = S x (for tests and for tiny matrices).
void SymmetricMultiplySerial(const BsmcMatrix& matrix, const double* x,
                             double* y);

}  // namespace dba
