// Rotations: R(ω) against Eigen's angle-axis, J_l(ω) against central
// differences of R(ω) X, on both sides of the Taylor branches.
#include "dba/camera/rotation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace dba {
namespace {

TEST(Rotation, RotationIsOrthonormalAndMatchesAxisAngle) {
  const Vec3 omega(0.3, -0.2, 0.5);
  const Mat3 R = AngleAxisToRotation(omega);
  EXPECT_LT((R * R.transpose() - Mat3::Identity()).norm(), 1e-14);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-14);
  EXPECT_LT((R * omega - omega).norm(), 1e-14);  // the axis is fixed
  const Eigen::AngleAxisd ref(omega.norm(), omega.normalized());
  EXPECT_LT((R - ref.toRotationMatrix()).norm(), 1e-14);
}

// d(R(ω) X)/dω = -[R X]ₓ J_l(ω), for large, small and Taylor-range angles.
TEST(Rotation, LeftJacobianMatchesCentralDifferences) {
  const Vec3 X(1.5, -0.7, 2.0);
  for (const Vec3& omega : {Vec3(0.3, -0.2, 0.5), Vec3(2.0, 1.0, -1.5), Vec3(1e-5, -2e-5, 1e-5)}) {
    const RotationFrame f = MakeRotationFrame(omega.data());
    const Mat3 analytic = -SkewSymmetric(f.R * X) * f.J_l;
    Mat3 numeric;
    const double h = 1e-6;
    for (int j = 0; j < 3; ++j) {
      Vec3 plus = omega, minus = omega;
      plus[j] += h, minus[j] -= h;
      numeric.col(j) = (AngleAxisToRotation(plus) * X - AngleAxisToRotation(minus) * X) / (2 * h);
    }
    EXPECT_LT((analytic - numeric).norm(), 1e-8) << omega.transpose();
    EXPECT_LT((f.R - AngleAxisToRotation(omega)).norm(), 1e-15);
  }
}

}  // namespace
}  // namespace dba
