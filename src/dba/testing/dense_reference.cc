// Dense references for tests; see dense_reference.h.
#include "dba/testing/dense_reference.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "dba/camera/bal_camera.h"

namespace dba::testing {

DenseNormalEquations BuildDenseNormalEquations(const BalProblem& problem,
                                               double lambda,
                                               const DampingBounds& bounds) {
  DenseNormalEquations d;
  const int64_t nc = problem.num_cameras(), np = problem.num_points();
  const int64_t no = problem.num_observations();
  d.num_camera_params = static_cast<int>(9 * nc);
  const int64_t cols = 9 * nc + 3 * np;
  d.J = Eigen::MatrixXd::Zero(2 * no, cols);
  d.r.resize(2 * no);
  for (int64_t k = 0; k < np; ++k) {
    for (int64_t obs = problem.point_offsets[k]; obs < problem.point_offsets[k + 1]; ++obs) {
      const int32_t i = problem.obs_camera[obs];
      CameraJacobian J_c;
      PointJacobian J_p;
      const Vec2 r = BalResidualAndJacobians(problem.camera(i), problem.point(k),
                                             problem.pixel(obs), &J_c, &J_p);
      d.J.block(2 * obs, 9 * i, 2, 9) = J_c;
      d.J.block(2 * obs, 9 * nc + 3 * k, 2, 3) = J_p;
      d.r.segment<2>(2 * obs) = r;
    }
  }
  d.cost = 0.5 * d.r.squaredNorm();
  d.H = d.J.transpose() * d.J;
  d.g = d.J.transpose() * d.r;
  for (int64_t c = 0; c < cols; ++c) d.H(c, c) += lambda * bounds.Clamp(d.H(c, c));
  return d;
}

Eigen::MatrixXd DenseNormalEquations::ReducedCameraMatrix() const {
  const int nc = num_camera_params;
  const int np = static_cast<int>(H.rows()) - nc;
  const Eigen::MatrixXd U = H.topLeftCorner(nc, nc);
  const Eigen::MatrixXd W = H.topRightCorner(nc, np);
  const Eigen::MatrixXd V = H.bottomRightCorner(np, np);
  return U - W * V.inverse() * W.transpose();
}

Eigen::VectorXd DenseNormalEquations::ReducedRhs() const {
  const int nc = num_camera_params;
  const int np = static_cast<int>(H.rows()) - nc;
  const Eigen::MatrixXd W = H.topRightCorner(nc, np);
  const Eigen::MatrixXd V = H.bottomRightCorner(np, np);
  return -g.head(nc) + W * V.inverse() * g.tail(np);
}

Eigen::VectorXd DenseNormalEquations::SolveStep() const {
  return H.ldlt().solve(-g);
}

Eigen::MatrixXd DenseFromBsmc(const BsmcMatrix& S) {
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(S.num_rows(), S.num_rows());
  for (int32_t i = 0; i < S.num_block_rows(); ++i) {
    for (int64_t b = S.row_begin(i); b < S.row_end(i); ++b) {
      const int32_t j = S.block_col(b);
      const int ri = S.block_size(i), cj = S.block_size(j);
      const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic,
                                           Eigen::RowMajor>>
          block(S.block_values(b), ri, cj);
      D.block(S.scalar_offset(i), S.scalar_offset(j), ri, cj) = block;
      if (j != i) D.block(S.scalar_offset(j), S.scalar_offset(i), cj, ri) = block.transpose();
    }
  }
  return D;
}

}  // namespace dba::testing
