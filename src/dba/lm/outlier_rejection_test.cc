// Outlier rejection: which observations and points go, what is left in what
// order, and where it came from.
#include "dba/lm/outlier_rejection.h"

#include <gtest/gtest.h>

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
  const RejectionRound round = DropOutliers(10.0, 2, &problem, &original);

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
  const RejectionRound again = DropOutliers(10.0, 1, &problem, &original);
  EXPECT_EQ(again.observations_dropped, 0);
  EXPECT_EQ(again.points_dropped, 0);
  EXPECT_EQ(problem.obs_pixel, after.obs_pixel);
}

}  // namespace
}  // namespace dba
