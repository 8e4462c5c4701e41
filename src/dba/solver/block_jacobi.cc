// Block-Jacobi preconditioner (paper eq. 7); see block_jacobi.h.
#include "dba/bsmc/block_shape.h"
#include "dba/common/check.h"
#include "dba/solver/block_jacobi.h"

#include <omp.h>

#include <algorithm>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace dba {

BlockJacobiPreconditioner::BlockJacobiPreconditioner(const BsmcMatrix& S, int num_threads,
                                                     int32_t num_block_rows)
    : S_(S),
      num_threads_(num_threads),
      n_(num_block_rows < 0 ? S.num_block_rows() : num_block_rows) {
  const int32_t n = n_;
  offset_.resize(n + 1);
  offset_[0] = 0;
  for (int32_t i = 0; i < n; ++i) {
    offset_[i + 1] = offset_[i] + int64_t{S.block_size(i)} * S.block_size(i);
  }
  inverse_.Resize(offset_[n]);
}

void BlockJacobiPreconditioner::Update(const BsmcMatrix& S) {
  AllocateNumeric();
  const int threads = n_ > 256 ? std::max(num_threads_, 1) : 1;
#pragma omp parallel num_threads(threads) if (threads > 1)
  {
    const int t = omp_get_thread_num(), team = omp_get_num_threads();
    UpdateRows(S, static_cast<int32_t>(int64_t{n_} * t / team),
               static_cast<int32_t>(int64_t{n_} * (t + 1) / team));
  }
}

// S_ii⁻¹ by Cholesky; a block that is not positive definite by LDLT with
// pivoting, or the inverse of its diagonal if that fails too. Fixed-size
// code for the camera models' blocks (no allocation per block).
void BlockJacobiPreconditioner::UpdateRows(const BsmcMatrix& S, int32_t begin, int32_t end) {
  DBA_DCHECK(!S.values_narrowed());
  double* inverse = inverse_.data();
  for (int32_t i = begin; i < end; ++i) {
    const int c = S.block_size(i);
    WithSquareBlockSize(c, [&]<int N>() {
      using Mat = Eigen::Matrix<double, N, N, Eigen::RowMajor>;
      const Eigen::Map<const Mat> block(S.block_values(S.diagonal_block(i)), c, c);
      Eigen::Map<Mat> inv(inverse + offset_[i], c, c);
      const Mat identity = Mat::Identity(c, c);
      const Eigen::LLT<Mat> llt(block);
      if (llt.info() == Eigen::Success) {
        inv = llt.solve(identity);
        return;
      }
      const Eigen::LDLT<Mat> ldlt(block);
      if (ldlt.info() == Eigen::Success && ldlt.isPositive()) {
        inv = ldlt.solve(identity);
        return;
      }
      inv.setZero();
      for (int d = 0; d < c; ++d) inv(d, d) = block(d, d) > 0 ? 1.0 / block(d, d) : 1.0;
    });
  }
}

void BlockJacobiPreconditioner::ApplyShare(const double* r, double* z, int part,
                                           int parts) const {
  const int32_t begin = static_cast<int32_t>(int64_t{n_} * part / parts);
  const int32_t end = static_cast<int32_t>(int64_t{n_} * (part + 1) / parts);
  for (int32_t i = begin; i < end; ++i) {
    const int c = S_.block_size(i);
    const int64_t o = S_.scalar_offset(i);
    WithSquareBlockSize(c, [&]<int N>() {
      using Vec = Eigen::Matrix<double, N, 1>;
      using Mat = Eigen::Matrix<double, N, N, Eigen::RowMajor>;
      Eigen::Map<Vec>(z + o, c).noalias() =
          Eigen::Map<const Mat>(inverse_.data() + offset_[i], c, c)
              .lazyProduct(Eigen::Map<const Vec>(r + o, c));
    });
  }
}

void BlockJacobiPreconditioner::Apply(const double* r, double* z) const {
  const int threads = n_ > 256 ? std::max(num_threads_, 1) : 1;
#pragma omp parallel num_threads(threads) if (threads > 1)
  ApplyShare(r, z, omp_get_thread_num(), omp_get_num_threads());
}

}  // namespace dba
