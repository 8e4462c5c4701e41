// The pose's step: a rotation step turns the camera about its own centre, a
// centre step moves the centre by exactly itself, and the step is the same
// motion wherever the world's origin is.
#include "dba/camera/pose_step.h"

#include <gtest/gtest.h>

#include <random>

#include "dba/camera/pose_similarity.h"

namespace dba {
namespace {

Mat3 RotationOf(const double* pose) { return AngleAxisToRotation(Vec3(pose[0], pose[1], pose[2])); }

TEST(PoseStep, RotationTurnsAboutTheCentreAndTheCentreStepMovesIt) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 100; ++trial) {
    const double pose[6] = {2 * u(rng), 2 * u(rng), 2 * u(rng), 900 * u(rng), 900 * u(rng),
                            900 * u(rng)};
    const double turn[6] = {0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng), 0, 0, 0};
    double turned[6];
    PlusPose(pose, turn, turned);
    EXPECT_LT((CameraCentre(turned) - CameraCentre(pose)).norm(), 1e-9);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(turned[k], pose[k] + turn[k]);

    const double move[6] = {0, 0, 0, 5 * u(rng), 5 * u(rng), 5 * u(rng)};
    double moved[6];
    PlusPose(pose, move, moved);
    EXPECT_LT((CameraCentre(moved) - CameraCentre(pose) - Vec3(move[3], move[4], move[5])).norm(),
              1e-9);
    EXPECT_LT((RotationOf(moved) - RotationOf(pose)).norm(), 1e-15);
  }
}

// Moving the world's origin by o (t → t + R o) and stepping gives the
// stepped pose with its origin moved: no step depends on where the origin is.
TEST(PoseStep, CommutesWithMovingTheOrigin) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Similarity shift;
  shift.translation = Vec3(-5e5, 4e6, 300);  // a projected CRS's origin
  for (int trial = 0; trial < 100; ++trial) {
    double pose[6] = {u(rng), u(rng), u(rng), 900 * u(rng), 900 * u(rng), 900 * u(rng)};
    const double delta[6] = {0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng),
                             5 * u(rng),   5 * u(rng),   5 * u(rng)};
    double stepped[6], shifted[6];
    PlusPose(pose, delta, stepped);
    MovePose(shift, stepped);
    std::copy(pose, pose + 6, shifted);
    MovePose(shift, shifted);
    PlusPose(shifted, delta, shifted);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(shifted[k], stepped[k], 1e-12);
    EXPECT_LT((CameraCentre(shifted) - CameraCentre(stepped)).norm(), 1e-7);
  }
}

}  // namespace
}  // namespace dba
