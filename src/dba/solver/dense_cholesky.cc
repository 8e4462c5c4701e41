// Dense Cholesky of the damped RCS; see dense_cholesky.h.
#include "dba/solver/dense_cholesky.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <algorithm>
#include <stdexcept>
#include <string>

#include <unistd.h>


namespace dba {

void ExpandUpperTriangle(const BsmcMatrix& S, double* dense) {
  const int64_t n = S.num_rows();
  for (int32_t i = 0; i < S.num_block_rows(); ++i) {
    const int ci = S.block_size(i);
    const int64_t oi = S.scalar_offset(i);
    for (int64_t blk = S.row_begin(i); blk < S.row_end(i); ++blk) {
      const int32_t j = S.block_col(blk);
      const int cj = S.block_size(j);
      const int64_t oj = S.scalar_offset(j);
      const double* v = S.block_values(blk);  // row-major ci x cj
      for (int a = 0; a < ci; ++a) {
        for (int c = 0; c < cj; ++c) dense[(oj + c) * n + oi + a] = v[a * cj + c];
      }
    }
  }
}

DenseCholeskySolver::DenseCholeskySolver(const BsmcMatrix& S) {
  const int64_t n = S.num_rows();
  const double bytes = static_cast<double>(n) * static_cast<double>(n) * 8.0;
  const double memory = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * sysconf(_SC_PAGESIZE);
  if (memory > 0 && bytes > 0.5 * memory) {
    throw std::runtime_error("dense Cholesky: " + std::to_string(n) + " unknowns need " +
                             std::to_string(static_cast<int64_t>(bytes / (1 << 20))) +
                             " MiB, more than half of this machine's memory; use "
                             "--linear-solver sparse or pcg");
  }
  dense_.resize(n * n);
  n_ = n;
}

int64_t DenseCholeskySolver::MemoryBytes() const {
  return static_cast<int64_t>(dense_.size()) * int64_t{sizeof(double)};
}

bool DenseCholeskySolver::Factorize(const BsmcMatrix& S) {
  const int64_t n = S.num_rows();
  // The last factorization filled blocks S does not store: start from zero.
  std::fill(dense_.begin(), dense_.end(), 0.0);
  ExpandUpperTriangle(S, dense_.data());
  Eigen::Map<Eigen::MatrixXd> dense(dense_.data(), n, n);
  Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Upper> llt(dense);  // in place
  return llt.info() == Eigen::Success;
}

void DenseCholeskySolver::SolveFactored(const double* b, double* x) {
  const int64_t n = n_;
  Eigen::Map<const Eigen::MatrixXd> factor(dense_.data(), n, n);  // U, S = Uᵀ U
  Eigen::Map<Eigen::VectorXd> solution(x, n);
  if (x != b) solution = Eigen::Map<const Eigen::VectorXd>(b, n);
  factor.transpose().triangularView<Eigen::Lower>().solveInPlace(solution);
  factor.triangularView<Eigen::Upper>().solveInPlace(solution);
}

}  // namespace dba
