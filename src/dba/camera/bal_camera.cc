// BAL camera projection and analytic Jacobians; see bal_camera.h.
#include "dba/camera/bal_camera.h"

#include <cmath>

namespace dba {

Vec2 BalResidual(const double* camera, const double* point,
                 const double* observed) {
  const Vec3 omega(camera[0], camera[1], camera[2]);
  const Vec3 t(camera[3], camera[4], camera[5]);
  const Vec3 P = AngleAxisToRotation(omega) * Vec3(point[0], point[1], point[2]) + t;
  const Vec2 p(-P.x() / P.z(), -P.y() / P.z());
  const double r2 = p.squaredNorm();
  const double d = 1.0 + r2 * (camera[7] + camera[8] * r2);
  return camera[6] * d * p - Vec2(observed[0], observed[1]);
}

Vec2 BalResidualAndJacobians(const double* camera, const double* point,
                             const double* observed, BalCameraJacobian* J_c,
                             PointJacobian* J_p) {
  return BalResidualAndJacobians(MakeRotationFrame(camera), camera, point, observed, J_c, J_p);
}

Vec2 BalResidualAndJacobians(const RotationFrame& frame, const double* camera,
                             const double* point, const double* observed, BalCameraJacobian* J_c,
                             PointJacobian* J_p) {
  const Vec3 t(camera[3], camera[4], camera[5]);
  const double f = camera[6], k1 = camera[7], k2 = camera[8];
  const Mat3& R = frame.R;
  const Vec3 RX = R * Vec3(point[0], point[1], point[2]);
  const Vec3 P = RX + t;
  const double inv_z = 1.0 / P.z();
  const Vec2 p(-P.x() * inv_z, -P.y() * inv_z);
  const double r2 = p.squaredNorm();
  const double d = 1.0 + r2 * (k1 + k2 * r2);

  // ∂u/∂P = ∂u/∂p ∂p/∂P  (2 x 3)
  Eigen::Matrix2d du_dp =
      f * (d * Eigen::Matrix2d::Identity() + 2.0 * (k1 + 2.0 * k2 * r2) * p * p.transpose());
  Eigen::Matrix<double, 2, 3> dp_dP;
  dp_dP << -inv_z, 0.0, P.x() * inv_z * inv_z, 0.0, -inv_z, P.y() * inv_z * inv_z;
  const Eigen::Matrix<double, 2, 3> du_dP = du_dp * dp_dP;

  if (J_c != nullptr) {
    J_c->block<2, 3>(0, 0) = -du_dP * SkewSymmetric(RX) * frame.J_l;
    J_c->block<2, 3>(0, 3) = du_dP;
    J_c->col(6) = d * p;
    J_c->col(7) = f * r2 * p;
    J_c->col(8) = f * r2 * r2 * p;
  }
  if (J_p != nullptr) *J_p = du_dP * R;
  return f * d * p - Vec2(observed[0], observed[1]);
}

}  // namespace dba
