// The camera-centre prior's Jacobian against central differences of the
// pose's step, and its centre against the camera's projection centre (the
// point every ray meets).
#include "dba/rcs/camera_centre_prior.h"

#include "dba/camera/pose_step.h"

#include <gtest/gtest.h>

#include <random>

namespace dba {
namespace {

TEST(CameraCentrePrior, JacobianMatchesCentralDifferences) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 500; ++trial) {
    const double scale = trial % 5 == 0 ? 1e-7 : 2.0;  // near θ = 0 too
    double pose[6] = {scale * u(rng), scale * u(rng), scale * u(rng),
                      50 * u(rng),    50 * u(rng),    50 * u(rng)};
    CameraCentrePrior prior;
    prior.centre = Vec3(10 * u(rng), 10 * u(rng), 10 * u(rng));
    prior.sigma = Vec3(0.5, 0.5, 2.0);
    CentrePriorJacobian J;
    const Vec3 r = CentrePriorResidual(pose, Vec3::Zero(), prior, &J);
    EXPECT_LT((r - CentrePriorResidual(pose, Vec3::Zero(), prior, nullptr)).norm(), 1e-12);
    for (int j = 0; j < kPoseSize; ++j) {
      auto residual_at = [&](double h) {  // on the pose's step (camera/pose_step.h)
        double delta[kPoseSize] = {}, moved[kPoseSize];
        delta[j] = h;
        PlusPose(pose, delta, moved);
        return CentrePriorResidual(moved, Vec3::Zero(), prior, nullptr);
      };
      const double h = 1e-6;
      const Vec3 numeric = (residual_at(h) - residual_at(-h)) / (2 * h);
      EXPECT_LT((numeric - J.col(j)).norm(), 1e-6 * (1 + J.col(j).norm()))
          << "trial " << trial << " parameter " << j;
    }
  }
}

TEST(CameraCentrePrior, CentreIsWhereTheCameraFrameHasItsOrigin) {
  const double pose[6] = {0.3, -0.2, 0.1, 4, -5, 6};
  const Vec3 C = CameraCentre(pose);
  const Mat3 R = AngleAxisToRotation(Vec3(pose[0], pose[1], pose[2]));
  EXPECT_LT((R * C + Vec3(pose[3], pose[4], pose[5])).norm(), 1e-12);
  CameraCentrePrior prior;
  prior.centre = C + Vec3(1, -2, 4);
  prior.sigma = Vec3(0.5, 0.5, 2);
  EXPECT_LT((CentrePriorResidual(pose, Vec3::Zero(), prior, nullptr) - Vec3(-2, 4, -2)).norm(), 1e-12);
}


// With a lever arm: the antenna's Jacobians on the pose's step and on the
// lever arm against central differences, and the antenna where the camera
// frame has the lever arm.
TEST(CameraCentrePrior, LeverArmJacobiansMatchCentralDifferences) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 300; ++trial) {
    const double scale = trial % 5 == 0 ? 1e-7 : 2.0;
    const double pose[6] = {scale * u(rng), scale * u(rng), scale * u(rng),
                            50 * u(rng),    50 * u(rng),    50 * u(rng)};
    const Vec3 a(2 * u(rng), 2 * u(rng), 2 * u(rng));
    CameraCentrePrior prior;
    prior.centre = Vec3(10 * u(rng), 10 * u(rng), 10 * u(rng));
    prior.sigma = Vec3(0.5, 0.5, 2.0);
    CentrePriorJacobian J;
    LeverArmJacobian J_a;
    CentrePriorResidual(pose, a, prior, &J, &J_a);
    const double h = 1e-6;
    for (int j = 0; j < kPoseSize; ++j) {
      auto residual_at = [&](double step) {
        double delta[kPoseSize] = {}, moved[kPoseSize];
        delta[j] = step;
        PlusPose(pose, delta, moved);
        return CentrePriorResidual(moved, a, prior, nullptr);
      };
      const Vec3 numeric = (residual_at(h) - residual_at(-h)) / (2 * h);
      EXPECT_LT((numeric - J.col(j)).norm(), 1e-6 * (1 + J.col(j).norm())) << trial << " " << j;
    }
    for (int j = 0; j < 3; ++j) {
      const Vec3 e = Vec3::Unit(j);
      const Vec3 numeric = (CentrePriorResidual(pose, a + h * e, prior, nullptr) -
                            CentrePriorResidual(pose, a - h * e, prior, nullptr)) / (2 * h);
      EXPECT_LT((numeric - J_a.col(j)).norm(), 1e-6 * (1 + J_a.col(j).norm())) << trial << " " << j;
    }
    // The camera's own frame maps the antenna to a: R P + t = a.
    const Mat3 R = AngleAxisToRotation(Vec3(pose[0], pose[1], pose[2]));
    EXPECT_LT((R * AntennaPosition(pose, a) + Vec3(pose[3], pose[4], pose[5]) - a).norm(), 1e-9);
  }
}

}  // namespace
}  // namespace dba
