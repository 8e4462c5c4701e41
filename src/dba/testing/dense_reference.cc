// Dense references for tests; see dense_reference.h.
#include "dba/testing/dense_reference.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "dba/camera/bal_camera.h"
#include "dba/camera/photo_camera.h"
#include "dba/camera/rig_pose.h"
#include "dba/rcs/unknown_layout.h"

namespace dba::testing {

DenseNormalEquations BuildDenseNormalEquations(const Problem& problem,
                                               double lambda,
                                               const DampingBounds& bounds,
                                               const RobustLoss& loss) {
  DenseNormalEquations d;
  const UnknownLayout layout(problem);
  const int64_t np = problem.num_points();
  const int64_t no = problem.num_observations();
  const int64_t nc = layout.num_unknowns();
  d.num_camera_params = static_cast<int>(nc);
  const int64_t cols = nc + 3 * np;
  const int64_t num_priors = static_cast<int64_t>(problem.point_priors.size());
  d.J = Eigen::MatrixXd::Zero(2 * no + 3 * num_priors, cols);
  d.r.resize(2 * no + 3 * num_priors);
  // Control points: 3 rows each after the observations', diag(w) on X.
  for (int64_t x = 0; x < num_priors; ++x) {
    const PointPrior& p = problem.point_priors[x];
    for (int a = 0; a < 3; ++a) {
      d.J(2 * no + 3 * x + a, nc + 3 * p.point + a) = p.weight[a];
      d.r[2 * no + 3 * x + a] = p.weight[a] * (problem.point(p.point)[a] - p.position[a]);
    }
  }
  for (int64_t k = 0; k < np; ++k) {
    for (int64_t obs = problem.point_offsets[k]; obs < problem.point_offsets[k + 1]; ++obs) {
      const int32_t i = problem.obs_camera[obs];
      const int32_t row = layout.camera_row(i);
      PointJacobian J_p;
      Vec2 r;
      if (problem.model == CameraModel::kBal) {
        BalCameraJacobian J_c;
        r = BalResidualAndJacobians(problem.camera(i), problem.point(k), problem.pixel(obs),
                                    &J_c, &J_p);
        if (row >= 0) d.J.block(2 * obs, layout.row_offset(row), 2, 9) = J_c;
      } else {
        // Columns of the free parameters only: the pose's 6, and each free
        // intrinsic parameter of the image's group in increasing order.
        const int32_t g = problem.camera_intrinsics[i];
        PoseJacobian J_pose;
        IntrinsicsJacobian J_in;
        r = PhotoResidualAndJacobians(problem.group_model(g), problem.camera(i),
                                      problem.intrinsics(g), problem.point(k),
                                      problem.pixel(obs), &J_pose, &J_in, &J_p);
        const int32_t grow = layout.intrinsics_row(g);
        int64_t col = grow >= 0 ? layout.row_offset(grow) : -1;
        for (int p = 0; p < problem.intrinsics_size && col >= 0; ++p) {
          if (problem.intrinsics_free_mask(g) & (1u << p)) d.J.block(2 * obs, col++, 2, 1) = J_in.col(p);
        }
        if (problem.has_rigs()) {
          // The frame's and (when refined) the sensor's columns instead of
          // the image's (camera/rig_pose.h).
          const double* frame = problem.cameras.data() + problem.frame_offset(problem.image_frame[i]);
          const double* sensor = problem.cameras.data() + problem.sensor_offset(g);
          const RotationFrame image = MakeRotationFrame(problem.camera(i));
          const Vec3 P = image.R * Eigen::Map<const Vec3>(problem.point(k)) +
                         Eigen::Map<const Vec3>(problem.camera(i) + 3);
          PoseJacobian J_sensor;
          RigResidualJacobians(MakeRigChain(MakeRotationFrame(frame), MakeRotationFrame(sensor), sensor),
                               image.R, P, J_p, &J_pose, &J_sensor);
          if (grow >= 0 && layout.intrinsic_unknowns(grow) < layout.block_size(grow)) {
            d.J.block(2 * obs, col, 2, 6) = J_sensor;
          }
        }
        if (row >= 0) d.J.block(2 * obs, layout.row_offset(row), 2, 6) = J_pose;
      }
      d.J.block(2 * obs, nc + 3 * k, 2, 3) = J_p;
      d.r.segment<2>(2 * obs) = r;
    }
  }
  // Weights per observation (identity for the squared loss).
  // The priors' rows under the squared loss (Ω = I).
  Eigen::MatrixXd omega = Eigen::MatrixXd::Identity(d.r.size(), d.r.size());
  Eigen::VectorXd weighted_r = d.r;
  d.cost = 0.5 * d.r.tail(3 * num_priors).squaredNorm();
  for (int64_t a = 0; a < no; ++a) {
    const Vec2 r = d.r.segment<2>(2 * a);
    double rho[3];
    loss.Evaluate(r.squaredNorm(), rho);
    d.cost += 0.5 * rho[0];
    Eigen::Matrix2d w = rho[1] * Eigen::Matrix2d::Identity();
    if (rho[2] > 0.0) w += 2.0 * rho[2] * r * r.transpose();
    omega.block<2, 2>(2 * a, 2 * a) = w;
    weighted_r.segment<2>(2 * a) = rho[1] * r;
  }
  d.H = d.J.transpose() * omega * d.J;
  d.g = d.J.transpose() * weighted_r;
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
  return SolveSymmetric(H, -g);
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

Eigen::VectorXd SolveSpd(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  return A.llt().solve(b);
}

Eigen::VectorXd SolveSymmetric(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  return A.ldlt().solve(b);
}

Eigen::MatrixXd Inverse(const Eigen::MatrixXd& A) { return A.inverse(); }

SymmetricEigen EigenOfSymmetric(const Eigen::MatrixXd& A) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(A);
  return {eig.eigenvalues(), eig.eigenvectors()};
}

}  // namespace dba::testing
