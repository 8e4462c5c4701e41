// Block-Jacobi preconditioner M = blockdiag(S_ii) for PCG (paper eq. 7):
// z = M⁻¹ r, each diagonal block inverted once per linear solve.
//
// Thread safety: Apply is const and uses its own threads.
#pragma once

#include <vector>

#include "dba/bsmc/bsmc_matrix.h"

namespace dba {

class BlockJacobiPreconditioner {
 public:
  // Inverts every diagonal block of S (Cholesky; a block that is not positive
  // definite is inverted by LDLT with pivoting, or replaced by the inverse of
  // its diagonal if that fails too).
  BlockJacobiPreconditioner(const BsmcMatrix& S, int num_threads);

  // z = M⁻¹ r.
  void Apply(const double* r, double* z) const;

  int64_t MemoryBytes() const {
    return static_cast<int64_t>(inverse_.capacity() * sizeof(double));
  }

 private:
  const BsmcMatrix& S_;
  std::vector<int64_t> offset_;  // start of block i's inverse
  std::vector<double> inverse_;
  int num_threads_;
};

}  // namespace dba
