// The unknowns the data leave undetermined, row by row; see
// undetermined_unknowns.h (docs/design.md §8).
#include "dba/precision/undetermined_unknowns.h"

#include <Eigen/Dense>

namespace dba {

UndeterminedUnknowns FindUndeterminedUnknowns(const BsmcMatrix& S) {
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  UndeterminedUnknowns out;
  for (int32_t r = 0; r < S.num_block_rows(); ++r) {
    const int n = S.block_size(r);
    const Eigen::Map<const RowMajor> stored(S.block_values(S.diagonal_block(r)), n, n);
    const Eigen::MatrixXd block = stored.selfadjointView<Eigen::Upper>();  // the upper triangle is S's
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(block);
    const Eigen::VectorXd& values = eigen.eigenvalues();
    int null = 0;
    while (null < n && !(values[null] > 1e-12 * values[n - 1])) ++null;
    if (null == 0) continue;
    out.rows.push_back(r);
    out.null.push_back(eigen.eigenvectors().leftCols(null));
    // The null basis's best-conditioned unknowns: with them pinned the
    // rest of the block is nonsingular.
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(eigen.eigenvectors().leftCols(null).transpose());
    for (int k = 0; k < null; ++k) out.pins.push_back(S.scalar_offset(r) + qr.colsPermutation().indices()[k]);
  }
  return out;
}

bool MovedByNullDirections(const Eigen::MatrixXd& null, const Eigen::MatrixXd& W_r) {
  return (W_r.transpose() * null).norm() > 1e-6 * W_r.norm();
}

}  // namespace dba
