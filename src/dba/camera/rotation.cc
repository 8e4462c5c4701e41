// Rotations by angle-axis vectors; see rotation.h.
#include "dba/camera/rotation.h"

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

}  // namespace dba
