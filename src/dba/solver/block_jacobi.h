// Block-Jacobi preconditioner M = blockdiag(S_ii) for PCG (paper eq. 7):
// z = M⁻¹ r, each diagonal block inverted once per linear solve.
//
// Thread safety: Apply is const and uses its own threads.
#pragma once

#include <vector>

#include "dba/bsmc/bsmc_matrix.h"
#include "dba/common/placed_doubles.h"
#include "dba/solver/preconditioner.h"

namespace dba {

class BlockJacobiPreconditioner : public Preconditioner {
 public:
  // Storage for the inverses of S's diagonal blocks (symbolic); S must
  // outlive the preconditioner and keep its structure. `num_block_rows`:
  // only the first rows (a rank's own rows of a distributed RCS, the rest
  // its halo); -1: all.
  BlockJacobiPreconditioner(const BsmcMatrix& S, int num_threads, int32_t num_block_rows = -1);

  // Inverts every diagonal block of S (Cholesky; a block that is not positive
  // definite is inverted by LDLT with pivoting, or replaced by the inverse of
  // its diagonal if that fails too).
  void Update(const BsmcMatrix& S) override;
  // Update for block rows [begin, end) only, on the calling thread (for a
  // team that shares out the rows itself), after AllocateNumeric on one
  // thread.
  void UpdateRows(const BsmcMatrix& S, int32_t begin, int32_t end);
  int32_t num_block_rows() const { return n_; }
  // The inverses' storage of its own allocated now (nothing where a place is
  // lent), so that several threads may then UpdateRows.
  void AllocateNumeric() { inverse_.data(); }
  void Apply(const double* r, double* z) const override;
  // z_i = S_ii⁻¹ r_i for share `part` of `parts` equal shares of the rows
  // only, on the calling thread.
  void ApplyShare(const double* r, double* z, int part, int parts) const;
  void ReturnNumericPages() override { inverse_.ReturnPages(); }
  int64_t NumericDoubles() const override { return inverse_.size(); }
  void PlaceNumeric(double* place) override { inverse_.Place(place); }
  int64_t MemoryBytes() const override { return inverse_.size() * static_cast<int64_t>(sizeof(double)); }

 private:
  const BsmcMatrix& S_;
  std::vector<int64_t> offset_;  // start of block i's inverse
  PlacedDoubles inverse_;  // the inverses, block i's at offset_[i]
  int num_threads_;
  int32_t n_;  // rows preconditioned
};

}  // namespace dba
