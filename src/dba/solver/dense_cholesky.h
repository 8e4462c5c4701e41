// Dense Cholesky solve of the damped RCS, S = Uᵀ U, for small systems:
// S's upper triangle is expanded from BSMC into an n x n column-major matrix
// (each block copied once), factorized in place by Eigen's blocked LLT (n³/3
// flops), and solved by two triangular solves (2 n² flops). n² doubles in all. A matrix that is not
// numerically positive definite is reported as such (the LM loop then
// rejects the step and raises the damping).
//
// Thread safety: one Solve at a time.
#pragma once

#include <vector>

#include "dba/solver/rcs_solver.h"

namespace dba {

class DenseCholeskySolver : public CholeskySolver {
 public:
  explicit DenseCholeskySolver(const BsmcMatrix& S);
  bool Factorize(const BsmcMatrix& S) override;
  void SolveFactored(const double* b, double* x) override;
  LinearSolverType type() const override { return LinearSolverType::kDense; }
  int64_t MemoryBytes() const override;

 private:
  int64_t n_ = 0;
  std::vector<double> dense_;  // column-major n x n, upper triangle used
};

// The upper triangle of S (BSMC) written into the column-major n x n array
// `dense`; entries S does not store (and the strictly lower triangle) are
// left as they were.
void ExpandUpperTriangle(const BsmcMatrix& S, double* dense);

}  // namespace dba
