// One process's point side walks the problem once: it stays in the walk's
// order from the first solve through a rejection round to the last solve,
// and every figure it hands out (points, cameras, what is kept, a round's
// poses) is in the order it was given, equal to an unwalked side's.
#include "dba/lm/local_point_side.h"

#include <gtest/gtest.h>

#include <cmath>

#include "dba/problem/point_order.h"
#include "dba/testing/scattered_survey.h"

namespace dba {
namespace {

LmOptions Tight() {
  LmOptions o;
  o.num_threads = 2;
  o.linear_solver.type = LinearSolverType::kDense;
  o.function_tolerance = 1e-12;
  return o;
}

double MaxDifference(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double d = 0;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}

TEST(LocalPointSide, WalksOnceAndHandsOutTheGivenOrder) {
  Problem given = testing::MakeScatteredSurvey("side_walk.dba", 30, 100, 5, 8).scattered;
  for (int64_t o = 0; o < given.num_observations(); o += 37) given.obs_pixel[2 * o] += 60.0;
  given.fixed_cameras.assign(given.num_images(), 0);  // the gauge: parameters compare
  given.fixed_cameras[0] = given.fixed_cameras[1] = 1;
  const std::vector<int64_t> walk = PointWalk(given);
  ASSERT_FALSE(walk.empty());
  Problem walked = given, plain = given;
  LocalPointSide a(&walked, walk), b(&plain, {});
  const LmOptions o = Tight();
  const double cost_a = a.Solve(o, {}, {}, {}).lm.final_cost;
  const double cost_b = b.Solve(o, {}, {}, {}).lm.final_cost;
  EXPECT_NEAR(cost_a, cost_b, 1e-9 * cost_b);
  std::vector<double> points_a, points_b, cameras_a, cameras_b;
  a.AllPoints(&points_a);
  EXPECT_NE(walked.points, points_a);  // between solves still in the walk's order
  PoseObservations poses_a, poses_b;
  const RejectionRound round_a = a.DropOutliers({4.0, 0.0}, 2, false, &poses_a);
  const RejectionRound round_b = b.DropOutliers({4.0, 0.0}, 2, false, &poses_b);
  ASSERT_GT(round_a.observations_dropped, 0);
  EXPECT_EQ(round_a.observations_dropped, round_b.observations_dropped);
  EXPECT_EQ(round_a.points_dropped, round_b.points_dropped);
  // The poses counted in the walk's numbering, named as given.
  ASSERT_EQ(poses_a.id.size(), poses_a.before.size());
  for (size_t i = 0; i < poses_a.id.size(); ++i) {
    EXPECT_EQ(poses_a.before[i], poses_b.before[poses_a.id[i]]);
    EXPECT_EQ(poses_a.after[i], poses_b.after[poses_a.id[i]]);
  }
  const double again_a = a.Solve(o, {}, {}, {}).lm.final_cost;
  const double again_b = b.Solve(o, {}, {}, {}).lm.final_cost;
  EXPECT_NEAR(again_a, again_b, 1e-9 * again_b);
  EXPECT_EQ(a.Kept().observation, b.Kept().observation);
  EXPECT_EQ(a.Kept().point, b.Kept().point);
  a.AllPoints(&points_a);
  b.AllPoints(&points_b);
  EXPECT_LE(MaxDifference(points_a, points_b), 1e-7);
  a.AllCameras(&cameras_a);
  b.AllCameras(&cameras_b);
  EXPECT_LE(MaxDifference(cameras_a, cameras_b), 1e-7);
  // Back in the order given: the kept points and observations as the
  // unwalked side holds them.
  a.EndSolves();
  EXPECT_EQ(walked.obs_camera, plain.obs_camera);
  EXPECT_EQ(walked.point_offsets, plain.point_offsets);
  EXPECT_EQ(walked.obs_pixel, plain.obs_pixel);
  EXPECT_LE(MaxDifference(walked.points, plain.points), 1e-7);
  EXPECT_LE(MaxDifference(walked.cameras, plain.cameras), 1e-7);
}

}  // namespace
}  // namespace dba
