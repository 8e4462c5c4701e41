// BAL camera projection and analytic Jacobians; see bal_camera.h.
#include "dba/camera/bal_camera.h"

#include <cmath>

namespace dba {

Mat3 SkewSymmetric(const Vec3& v) {
  Mat3 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Mat3 AngleAxisToRotation(const Vec3& omega) {
  const double theta2 = omega.squaredNorm();
  const Mat3 K = SkewSymmetric(omega);
  if (theta2 < 1e-16) {
    // Second-order Taylor expansion: R = I + K + K²/2.
    return Mat3::Identity() + K + 0.5 * K * K;
  }
  const double theta = std::sqrt(theta2);
  const double a = std::sin(theta) / theta;
  const double b = (1.0 - std::cos(theta)) / theta2;
  return Mat3::Identity() + a * K + b * K * K;
}

Mat3 SO3LeftJacobian(const Vec3& omega) {
  const double theta2 = omega.squaredNorm();
  const Mat3 K = SkewSymmetric(omega);
  double a, b;
  if (theta2 < 1e-8) {
    // Taylor: (1 - cos θ)/θ² = 1/2 - θ²/24, (θ - sin θ)/θ³ = 1/6 - θ²/120.
    a = 0.5 - theta2 / 24.0;
    b = 1.0 / 6.0 - theta2 / 120.0;
  } else {
    const double theta = std::sqrt(theta2);
    a = (1.0 - std::cos(theta)) / theta2;
    b = (theta - std::sin(theta)) / (theta2 * theta);
  }
  return Mat3::Identity() + a * K + b * K * K;
}

RotationFrame MakeRotationFrame(const double* omega) {
  const Vec3 w(omega[0], omega[1], omega[2]);
  return {AngleAxisToRotation(w), SO3LeftJacobian(w)};
}

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
                             const double* observed, CameraJacobian* J_c,
                             PointJacobian* J_p) {
  return BalResidualAndJacobians(MakeRotationFrame(camera), camera, point, observed, J_c, J_p);
}

Vec2 BalResidualAndJacobians(const RotationFrame& frame, const double* camera,
                             const double* point, const double* observed, CameraJacobian* J_c,
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
