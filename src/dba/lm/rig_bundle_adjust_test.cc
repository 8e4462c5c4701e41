// Bundle adjustment with rigs (docs/design.md §1.7): the optimum reaches the
// noise floor of the rig's unknowns with a zero gradient in them, held
// sensor poses stay put bit for bit while the images follow their frames,
// and thread counts agree.
#include <gtest/gtest.h>

#include <cmath>

#include "dba/camera/rig_pose.h"
#include "dba/lm/bundle_adjust.h"
#include "dba/rcs/unknown_layout.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/synthetic_rig.h"

namespace dba {
namespace {

testing::SyntheticProblem RingProblem(bool held) {
  testing::SyntheticRigOptions o;
  o.frames = 10;
  o.sensors = 3;
  o.points = 120;
  o.missing = true;
  o.held_geometry = held;
  o.pixel_noise = 0.5;
  o.seed = 7;
  testing::SyntheticProblem s = testing::MakeSyntheticRig(o);
  // The principal points held (as dba solve does by default): a sensor's
  // small turn and its principal point's shift are nearly one motion.
  s.problem.fixed_intrinsics.assign(s.problem.num_groups(), kIntrinsicCx | kIntrinsicCy);
  return s;
}

LmOptions Tight(int threads) {
  LmOptions options;
  options.num_threads = threads;
  options.function_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  options.gradient_tolerance = 1e-14;
  options.max_iterations = 50;
  return options;
}

TEST(RigBundleAdjust, ReachesTheNoiseFloorWithAZeroGradient) {
  testing::SyntheticProblem s = RingProblem(false);
  Problem& p = s.problem;
  const BundleAdjustSummary summary = BundleAdjust(Tight(2), &p);
  EXPECT_NE(summary.lm.termination, TerminationReason::kLambdaTooLarge);
  // 10 frames of 6, three groups of 5 intrinsics and two sensors of 6.
  const UnknownLayout layout(p);
  EXPECT_EQ(layout.num_unknowns(), 10 * 6 + 3 * 3 + 2 * 6);
  const double n = static_cast<double>(p.num_observations());
  const double unknowns = static_cast<double>(layout.num_unknowns() + 3 * p.num_points());
  const double expected_rms = 0.5 * std::sqrt(2.0) * std::sqrt(1.0 - unknowns / (2 * n));
  EXPECT_NEAR(summary.lm.Rms(summary.lm.final_cost), expected_rms, 0.1 * expected_rms);
  // The gradient in every unknown (frames, intrinsics, sensors, points) at
  // the optimum, against its size at the start.
  const auto end = testing::BuildDenseNormalEquations(p, 0.0, DampingBounds{});
  const auto start = testing::BuildDenseNormalEquations(RingProblem(false).problem, 0.0, DampingBounds{});
  EXPECT_LT(end.g.cwiseAbs().maxCoeff(), 1e-7 * start.g.cwiseAbs().maxCoeff());
  // Images stay composed from their frames and sensors.
  CameraSide composed = p.camera_side();
  ComposeRigImages(&composed);
  for (int64_t j = 0; j < kPhotoPoseSize * p.num_images(); ++j) {
    EXPECT_EQ(composed.cameras[j], p.cameras[j]) << j;
  }
  // The sensors come closer to the truth than they started.
  for (int64_t g = 1; g < p.num_groups(); ++g) {
    const double* solved = p.cameras.data() + p.sensor_offset(g);
    const double* truth = s.truth.cameras.data() + s.truth.sensor_offset(g);
    const double* initial = RingProblem(false).problem.cameras.data() + p.sensor_offset(g);
    const Vec3 e(solved[0] - truth[0], solved[1] - truth[1], solved[2] - truth[2]);
    const Vec3 e0(initial[0] - truth[0], initial[1] - truth[1], initial[2] - truth[2]);
    EXPECT_LT(e.norm(), 0.5 * e0.norm()) << "sensor " << g;
  }
}

TEST(RigBundleAdjust, HeldSensorPosesStayPut) {
  testing::SyntheticProblem s = RingProblem(true);
  Problem& p = s.problem;
  const std::vector<double> before = p.cameras;
  const BundleAdjustSummary summary = BundleAdjust(Tight(2), &p);
  EXPECT_LT(summary.lm.final_cost, 0.1 * summary.lm.initial_cost);
  for (int64_t g = 0; g < p.num_groups(); ++g) {
    for (int k = 0; k < 6; ++k) {
      EXPECT_EQ(p.cameras[p.sensor_offset(g) + k], before[p.sensor_offset(g) + k]);
    }
  }
  // The frames moved, and the images with them.
  EXPECT_NE(p.cameras[p.frame_offset(3)], before[p.frame_offset(3)]);
  EXPECT_NE(p.cameras[0], before[0]);
}

TEST(RigBundleAdjust, OneAndTwoThreadsAgree) {
  testing::SyntheticProblem a = RingProblem(false), b = RingProblem(false);
  const BundleAdjustSummary one = BundleAdjust(Tight(1), &a.problem);
  const BundleAdjustSummary two = BundleAdjust(Tight(2), &b.problem);
  EXPECT_NEAR(one.lm.final_cost, two.lm.final_cost, 1e-9 * one.lm.final_cost);
}

}  // namespace
}  // namespace dba
