// Analytic Jacobians of the photogrammetric camera against central
// differences, and its agreement with the BAL model it generalizes.
#include "dba/camera/photo_camera.h"
#include "dba/camera/bal_camera.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

namespace dba {
namespace {

struct Sample {
  double pose[6];
  double intrinsics[5];
  double point[3];
  double observed[2];
};

Sample RandomSample(std::mt19937& rng, double rotation_scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Sample s;
  for (int i = 0; i < 3; ++i) s.pose[i] = rotation_scale * u(rng);
  const Mat3 R = AngleAxisToRotation(Vec3(s.pose[0], s.pose[1], s.pose[2]));
  const Vec3 X(5 * u(rng), 5 * u(rng), 5 * u(rng));
  const Vec3 P(u(rng), u(rng), 3.0 + 2.0 * std::abs(u(rng)));  // in front: +z
  const Vec3 t = P - R * X;
  for (int i = 0; i < 3; ++i) s.pose[3 + i] = t[i], s.point[i] = X[i];
  s.intrinsics[0] = 1000 + 200 * u(rng);
  s.intrinsics[1] = 640 + 10 * u(rng);
  s.intrinsics[2] = 480 + 10 * u(rng);
  s.intrinsics[3] = 0.1 * u(rng);
  s.intrinsics[4] = 0.01 * u(rng);
  s.observed[0] = 600 + 50 * u(rng);
  s.observed[1] = 500 + 50 * u(rng);
  return s;
}

TEST(PhotoCamera, JacobiansMatchCentralDifferences) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 1000; ++trial) {
    Sample s = RandomSample(rng, trial % 4 == 0 ? 1e-7 : 2.0);
    PoseJacobian J_pose;
    IntrinsicsJacobian J_intr;
    PointJacobian J_point;
    const Vec2 r0 = PhotoResidualAndJacobians(s.pose, s.intrinsics, s.point, s.observed,
                                              &J_pose, &J_intr, &J_point);
    EXPECT_LT((r0 - PhotoResidual(s.pose, s.intrinsics, s.point, s.observed)).norm(), 1e-12);
    for (int j = 0; j < 14; ++j) {
      double* x = j < 6 ? &s.pose[j] : j < 11 ? &s.intrinsics[j - 6] : &s.point[j - 11];
      const double x0 = *x;
      const double h = 1e-6 * std::max(1.0, std::abs(x0));
      *x = x0 + h;
      const Vec2 plus = PhotoResidual(s.pose, s.intrinsics, s.point, s.observed);
      *x = x0 - h;
      const Vec2 minus = PhotoResidual(s.pose, s.intrinsics, s.point, s.observed);
      *x = x0;
      const Vec2 numeric = (plus - minus) / (2 * h);
      const Vec2 analytic = j < 6 ? Vec2(J_pose.col(j))
                            : j < 11 ? Vec2(J_intr.col(j - 6))
                                     : Vec2(J_point.col(j - 11));
      EXPECT_LT((numeric - analytic).norm(), 1e-5 * (1.0 + analytic.norm()))
          << "trial " << trial << " parameter " << j;
    }
  }
}

// COLMAP -> BAL (data/README.md): R_bal = diag(1,-1,-1) R, t_bal = diag(1,-1,-1) t,
// x_bal = x - cx, y_bal = -(y - cy). Both models give the same residual up
// to the sign of y.
TEST(PhotoCamera, AgreesWithTheBalModelUnderTheColmapMapping) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 100; ++trial) {
    Sample s = RandomSample(rng, 2.0);
    const Mat3 flip = Vec3(1, -1, -1).asDiagonal();
    const Mat3 R_bal = flip * AngleAxisToRotation(Vec3(s.pose[0], s.pose[1], s.pose[2]));
    const Eigen::AngleAxisd aa(R_bal);
    const Vec3 omega_bal = aa.angle() * aa.axis();
    const Vec3 t_bal = flip * Vec3(s.pose[3], s.pose[4], s.pose[5]);
    const double bal[9] = {omega_bal[0], omega_bal[1], omega_bal[2], t_bal[0], t_bal[1],
                           t_bal[2], s.intrinsics[0], s.intrinsics[3], s.intrinsics[4]};
    const double observed_bal[2] = {s.observed[0] - s.intrinsics[1],
                                    -(s.observed[1] - s.intrinsics[2])};
    const Vec2 r = PhotoResidual(s.pose, s.intrinsics, s.point, s.observed);
    const Vec2 r_bal = BalResidual(bal, s.point, observed_bal);
    EXPECT_NEAR(r_bal.x(), r.x(), 1e-8 * (1 + r.norm()));
    EXPECT_NEAR(r_bal.y(), -r.y(), 1e-8 * (1 + r.norm()));
  }
}

}  // namespace
}  // namespace dba
