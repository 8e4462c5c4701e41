// Outlier rejection: which observations and points go, what is left in what
// order, and where it came from.
#include "dba/lm/outlier_rejection.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "dba/camera/observation_residual.h"
#include "dba/testing/synthetic_bal.h"

namespace dba {
namespace {

TEST(DropOutliers, DropsFarObservationsAndPointsLeftWithOne) {
  testing::SyntheticBalOptions o;
  o.num_cameras = 6;
  o.num_points = 40;
  o.max_track = 4;
  o.pixel_noise = 0.5;
  Problem problem = testing::MakeSyntheticBal(o).problem;
  const Problem loaded = problem;
  // Moved by 30 px: every third observation of the problem, and all but one
  // observation of point 5 (which then has one left and goes).
  std::vector<uint8_t> moved(problem.num_observations(), 0);
  for (int64_t a = 0; a < problem.num_observations(); a += 3) moved[a] = 1;
  for (int64_t a = problem.point_offsets[5] + 1; a < problem.point_offsets[6]; ++a) moved[a] = 1;
  for (int64_t a = 0; a < problem.num_observations(); ++a) {
    if (moved[a]) problem.obs_pixel[2 * a] += 30.0;
  }
  const Problem before = problem;
  OriginalIndices original = OriginalIndices::Identity(problem);
  const RejectionRound round = DropOutliers({10.0, 0.0}, 2, &problem, &original);

  // Expected: per point, the unmoved observations, if at least 2.
  int64_t expected_obs = 0, expected_points = 0;
  for (int64_t k = 0; k < before.num_points(); ++k) {
    int64_t kept = 0;
    for (int64_t a = before.point_offsets[k]; a < before.point_offsets[k + 1]; ++a) kept += !moved[a];
    if (kept >= 2) expected_obs += kept, ++expected_points;
  }
  EXPECT_EQ(round.observations_left, expected_obs);
  EXPECT_EQ(round.points_left, expected_points);
  EXPECT_EQ(round.observations_dropped, before.num_observations() - expected_obs);
  EXPECT_EQ(round.points_dropped, before.num_points() - expected_points);
  ASSERT_EQ(problem.num_observations(), expected_obs);
  ASSERT_EQ(problem.num_points(), expected_points);
  EXPECT_EQ(problem.point_offsets.front(), 0);
  EXPECT_EQ(problem.point_offsets.back(), expected_obs);
  for (int64_t k = 0; k < problem.num_points(); ++k) {
    EXPECT_NE(original.point[k], 5);
    EXPECT_GE(problem.point_offsets[k + 1] - problem.point_offsets[k], 2);
    for (int d = 0; d < 3; ++d) EXPECT_EQ(problem.point(k)[d], before.point(original.point[k])[d]);
    for (int64_t a = problem.point_offsets[k]; a < problem.point_offsets[k + 1]; ++a) {
      const int64_t from = original.observation[a];
      EXPECT_FALSE(moved[from]);
      EXPECT_GE(from, before.point_offsets[original.point[k]]);
      EXPECT_LT(from, before.point_offsets[original.point[k] + 1]);
      EXPECT_EQ(problem.obs_camera[a], before.obs_camera[from]);
      EXPECT_EQ(problem.pixel(a)[0], before.pixel(from)[0]);
      EXPECT_EQ(problem.pixel(a)[1], before.pixel(from)[1]);
    }
  }
  EXPECT_EQ(problem.cameras, loaded.cameras);

  // A second round with nothing left to drop changes nothing.
  const Problem after = problem;
  const RejectionRound again = DropOutliers({10.0, 0.0}, 1, &problem, &original);
  EXPECT_EQ(again.observations_dropped, 0);
  EXPECT_EQ(again.points_dropped, 0);
  EXPECT_EQ(problem.obs_pixel, after.obs_pixel);
}

// Three BAL cameras without rotation (centre -t) at (0,0,0), (1,0,0) and
// (0,10,0), one point at (0,0,10): rays (0,0,10), (-1,0,10), (0,-10,10); the
// widest pair is the second and the third, acos(100 / sqrt(101 * 200)).
TEST(DropOutliers, TriangulationAngleIsTheWidestPairOfRays) {
  Problem p;
  p.cameras.assign(3 * kBalCameraSize, 0.0);
  p.cameras[kBalCameraSize + 3] = -1.0;
  p.cameras[2 * kBalCameraSize + 4] = -10.0;
  for (int i = 0; i < 3; ++i) p.cameras[i * kBalCameraSize + 6] = 1000.0;  // focal
  p.points = {0.0, 0.0, 10.0};
  p.point_offsets = {0, 3};
  p.obs_camera = {0, 1, 2};
  p.obs_pixel.assign(6, 0.0);
  const std::vector<uint8_t> all = {1, 1, 1}, first_two = {1, 1, 0};
  const std::vector<double> centres = CameraCentres(p);
  EXPECT_NEAR(centres[3], 1.0, 1e-15);
  EXPECT_NEAR(centres[7], 10.0, 1e-15);
  EXPECT_NEAR(MaxTriangulationAngle(p, centres, 0, all.data()), std::acos(100.0 / std::sqrt(101.0 * 200.0)), 1e-12);
  EXPECT_NEAR(MaxTriangulationAngle(p, centres, 0, first_two.data()), std::atan(0.1), 1e-12);
}

// With a minimum angle, the points whose rays meet under it go though their
// observations fit; the rest stay whole.
TEST(DropOutliers, PointsUnderTheMinimumTriangulationAngleGo) {
  testing::SyntheticBalOptions o;
  o.num_cameras = 8;
  o.num_points = 60;
  o.max_track = 5;
  Problem problem = testing::MakeSyntheticBal(o).problem;
  const std::vector<double> centres = CameraCentres(problem);
  std::vector<uint8_t> all(problem.num_observations(), 1);
  std::vector<double> angles(problem.num_points());
  for (int64_t k = 0; k < problem.num_points(); ++k) {
    angles[k] = MaxTriangulationAngle(problem, centres, k, all.data()) * 180.0 / M_PI;
  }
  std::vector<double> sorted = angles;
  std::sort(sorted.begin(), sorted.end());
  const double threshold = sorted[sorted.size() / 2];  // about half the points go
  int64_t under = 0;
  for (double a : angles) under += a < threshold;
  ASSERT_GT(under, 0);
  OriginalIndices original = OriginalIndices::Identity(problem);
  const Problem before = problem;
  const RejectionRound round = DropOutliers({1e9, threshold}, 2, &problem, &original);
  EXPECT_EQ(round.points_small_angle, under);
  EXPECT_EQ(round.points_dropped, under);
  EXPECT_EQ(problem.num_points(), before.num_points() - under);
  for (int64_t k = 0; k < problem.num_points(); ++k) EXPECT_GE(angles[original.point[k]], threshold);
  // Off (0): nothing goes for its angle.
  const RejectionRound off = DropOutliers({1e9, 0.0}, 1, &problem, &original);
  EXPECT_EQ(off.points_dropped, 0);
}

}  // namespace
}  // namespace dba
