// Analytic Jacobians of the BAL camera against central differences.
#include "dba/camera/bal_camera.h"

#include "dba/camera/pose_step.h"

#include <gtest/gtest.h>

#include <random>

namespace dba {
namespace {

struct Sample {
  double camera[9];
  double point[3];
  double observed[2];
};

// A camera looking down -z at a point in front of it, with a random rotation
// (angles from 0 up to about π, and some near zero to hit the Taylor branch).
Sample RandomSample(std::mt19937& rng, double rotation_scale) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Sample s;
  for (int i = 0; i < 3; ++i) s.camera[i] = rotation_scale * u(rng);
  const Mat3 R = AngleAxisToRotation(Vec3(s.camera[0], s.camera[1], s.camera[2]));
  const Vec3 X(u(rng) * 5, u(rng) * 5, u(rng) * 5);
  // Choose t so that P = R X + t lies in front of the camera (P.z < 0).
  const Vec3 P(u(rng), u(rng), -3.0 - 2.0 * std::abs(u(rng)));
  const Vec3 t = P - R * X;
  for (int i = 0; i < 3; ++i) s.camera[3 + i] = t[i];
  s.camera[6] = 500.0 + 100.0 * u(rng);
  s.camera[7] = 0.1 * u(rng);
  s.camera[8] = 0.01 * u(rng);
  for (int i = 0; i < 3; ++i) s.point[i] = X[i];
  s.observed[0] = 10 * u(rng);
  s.observed[1] = 10 * u(rng);
  return s;
}

TEST(BalCamera, ResidualMatchesWithAndWithoutJacobians) {
  std::mt19937 rng(1);
  for (int trial = 0; trial < 100; ++trial) {
    Sample s = RandomSample(rng, 2.0);
    BalCameraJacobian J_c;
    PointJacobian J_p;
    const Vec2 a = BalResidual(s.camera, s.point, s.observed);
    const Vec2 b = BalResidualAndJacobians(s.camera, s.point, s.observed, &J_c, &J_p);
    EXPECT_LT((a - b).norm(), 1e-12 * (1 + a.norm()));
  }
}

TEST(BalCamera, JacobiansMatchCentralDifferences) {
  std::mt19937 rng(42);
  for (int trial = 0; trial < 1000; ++trial) {
    // A quarter of the cameras have tiny rotations (Taylor branches).
    Sample s = RandomSample(rng, trial % 4 == 0 ? 1e-6 : 2.0);
    BalCameraJacobian J_c;
    PointJacobian J_p;
    BalResidualAndJacobians(s.camera, s.point, s.observed, &J_c, &J_p);
    for (int j = 0; j < 12; ++j) {
      // The pose's columns are on its step (camera/pose_step.h), the others
      // on the parameters.
      auto residual_at = [&](double h) {
        Sample moved = s;
        if (j < kPoseSize) {
          double delta[kPoseSize] = {};
          delta[j] = h;
          PlusPose(s.camera, delta, moved.camera);
        } else {
          (j < 9 ? moved.camera[j] : moved.point[j - 9]) += h;
        }
        return BalResidual(moved.camera, moved.point, moved.observed);
      };
      const double x0 = j < kPoseSize ? 0.0 : j < 9 ? s.camera[j] : s.point[j - 9];
      const double h = 1e-6 * std::max(1.0, std::abs(x0));
      const Vec2 numeric = (residual_at(h) - residual_at(-h)) / (2 * h);
      const Vec2 analytic = j < 9 ? Vec2(J_c.col(j)) : Vec2(J_p.col(j - 9));
      EXPECT_LT((numeric - analytic).norm(), 1e-5 * (1.0 + analytic.norm()))
          << "trial " << trial << " parameter " << j;
    }
  }
}

}  // namespace
}  // namespace dba
