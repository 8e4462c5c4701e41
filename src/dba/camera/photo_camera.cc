// Photogrammetric camera projection and Jacobians; see photo_camera.h.
#include "dba/camera/photo_camera.h"

namespace dba {

Vec2 PhotoResidual(const double* pose, const double* intrinsics, const double* point,
                   const double* observed) {
  return PhotoResidualAndJacobians(pose, intrinsics, point, observed, nullptr, nullptr,
                                   nullptr);
}

Vec2 PhotoResidualAndJacobians(const double* pose, const double* intrinsics,
                               const double* point, const double* observed,
                               PoseJacobian* J_pose, IntrinsicsJacobian* J_intrinsics,
                               PointJacobian* J_point) {
  return PhotoResidualAndJacobians(MakeRotationFrame(pose), pose, intrinsics, point, observed,
                                   J_pose, J_intrinsics, J_point);
}

Vec2 PhotoResidualAndJacobians(const RotationFrame& frame, const double* pose,
                               const double* intrinsics, const double* point,
                               const double* observed, PoseJacobian* J_pose,
                               IntrinsicsJacobian* J_intrinsics, PointJacobian* J_point) {
  const Vec3 t(pose[3], pose[4], pose[5]);
  const double f = intrinsics[0], cx = intrinsics[1], cy = intrinsics[2];
  const double k1 = intrinsics[3], k2 = intrinsics[4];
  const Mat3& R = frame.R;
  const Vec3 RX = R * Vec3(point[0], point[1], point[2]);
  const Vec3 P = RX + t;
  const double inv_z = 1.0 / P.z();
  const Vec2 p(P.x() * inv_z, P.y() * inv_z);
  const double r2 = p.squaredNorm();
  const double d = 1.0 + r2 * (k1 + k2 * r2);
  const Vec2 u(f * d * p.x() + cx, f * d * p.y() + cy);
  if (J_pose != nullptr || J_point != nullptr) {
    const Eigen::Matrix2d du_dp =
        f * (d * Eigen::Matrix2d::Identity() + 2.0 * (k1 + 2.0 * k2 * r2) * p * p.transpose());
    Eigen::Matrix<double, 2, 3> dp_dP;
    dp_dP << inv_z, 0.0, -P.x() * inv_z * inv_z, 0.0, inv_z, -P.y() * inv_z * inv_z;
    const Eigen::Matrix<double, 2, 3> du_dP = du_dp * dp_dP;
    if (J_pose != nullptr) {
      J_pose->block<2, 3>(0, 0) = -du_dP * SkewSymmetric(RX) * frame.J_l;
      J_pose->block<2, 3>(0, 3) = du_dP;
    }
    if (J_point != nullptr) *J_point = du_dP * R;
  }
  if (J_intrinsics != nullptr) {
    J_intrinsics->col(0) = d * p;
    J_intrinsics->col(1) = Vec2(1.0, 0.0);
    J_intrinsics->col(2) = Vec2(0.0, 1.0);
    J_intrinsics->col(3) = f * r2 * p;
    J_intrinsics->col(4) = f * r2 * r2 * p;
  }
  return u - Vec2(observed[0], observed[1]);
}

}  // namespace dba
