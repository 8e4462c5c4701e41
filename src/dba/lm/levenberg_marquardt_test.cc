// The LM loop on synthetic problems with a known optimum.
#include "dba/lm/levenberg_marquardt.h"

#include <gtest/gtest.h>

#include "dba/camera/bal_camera.h"
#include "dba/lm/bundle_adjust.h"
#include "dba/testing/synthetic_bal.h"

namespace dba {
namespace {

testing::SyntheticProblem MakeProblem(double noise, uint32_t seed) {
  testing::SyntheticBalOptions o;
  o.num_cameras = 8;
  o.num_points = 200;
  o.max_track = 5;
  o.pixel_noise = noise;
  o.rotation_perturbation = 0.02;
  o.translation_perturbation = 0.1;
  o.point_perturbation = 0.1;
  o.intrinsics_perturbation = 0.01;
  o.seed = seed;
  return testing::MakeSyntheticBal(o);
}

double Cost(const Problem& p) {
  double c = 0.0;
  for (int64_t k = 0; k < p.num_points(); ++k) {
    for (int64_t obs = p.point_offsets[k]; obs < p.point_offsets[k + 1]; ++obs) {
      c += 0.5 * BalResidual(p.camera(p.obs_camera[obs]), p.point(k), p.pixel(obs))
                     .squaredNorm();
    }
  }
  return c;
}

TEST(LevenbergMarquardt, NoiseFreeProblemConvergesToZeroCost) {
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    testing::SyntheticProblem s = MakeProblem(0.0, seed);
    LmOptions options;
    options.num_threads = 2;
    options.function_tolerance = 1e-12;
    const LmSummary summary = BundleAdjust(options, &s.problem).lm;
    EXPECT_GT(summary.initial_cost, 1e3) << "seed " << seed;
    EXPECT_LT(summary.final_cost, 1e-12 * summary.initial_cost) << "seed " << seed;
    EXPECT_NEAR(Cost(s.problem), summary.final_cost, 1e-9 * summary.initial_cost);
    EXPECT_NE(summary.termination, TerminationReason::kMaxIterations);
    EXPECT_NE(summary.termination, TerminationReason::kLambdaTooLarge);
  }
}

TEST(LevenbergMarquardt, NoisyProblemEndsBelowTheTruthAtAStationaryPoint) {
  testing::SyntheticProblem s = MakeProblem(1.0, 7);
  const double truth_cost = Cost([&] {
    Problem t = s.truth;
    t.obs_pixel = s.problem.obs_pixel;  // true parameters, noisy pixels
    return t;
  }());
  LmOptions options;
  options.num_threads = 1;
  options.function_tolerance = 1e-10;
  const LmSummary summary = BundleAdjust(options, &s.problem).lm;
  // The optimum is at most the cost at the true parameters, and about
  // σ²/2 (2 n_obs - n_params) for σ = 1 px: well above zero.
  EXPECT_LE(summary.final_cost, truth_cost);
  EXPECT_GT(summary.final_cost, 0.3 * truth_cost);
  EXPECT_NEAR(summary.Rms(summary.final_cost), 1.0, 0.25);
  // Costs in the history never increase on accepted steps.
  for (size_t i = 1; i < summary.history.size(); ++i) {
    EXPECT_LE(summary.history[i].cost, summary.history[i - 1].cost * (1 + 1e-12));
  }
}

TEST(LevenbergMarquardt, IterationLimitIsReportedByName) {
  testing::SyntheticProblem s = MakeProblem(1.0, 3);
  LmOptions options;
  options.max_iterations = 2;
  const LmSummary summary = BundleAdjust(options, &s.problem).lm;
  EXPECT_EQ(summary.iterations, 2);
  EXPECT_EQ(summary.termination, TerminationReason::kMaxIterations);
  EXPECT_STREQ(TerminationReasonName(summary.termination), "max_iterations");
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  EXPECT_NEAR(Cost(s.problem), summary.final_cost, 1e-9 * summary.final_cost);
}

TEST(LevenbergMarquardt, ZeroIterationsLeavesTheProblemUntouched) {
  testing::SyntheticProblem s = MakeProblem(1.0, 3);
  const Problem before = s.problem;
  LmOptions options;
  options.max_iterations = 0;
  const LmSummary summary = BundleAdjust(options, &s.problem).lm;
  EXPECT_EQ(summary.iterations, 0);
  EXPECT_EQ(summary.final_cost, summary.initial_cost);
  EXPECT_EQ(s.problem.cameras, before.cameras);
  EXPECT_EQ(s.problem.points, before.points);
}

TEST(LevenbergMarquardt, GradientToleranceStopsAtTheOptimum) {
  testing::SyntheticProblem s = MakeProblem(0.0, 2);
  s.problem = s.truth;  // already optimal: zero residuals, zero gradient
  LmOptions options;
  options.gradient_tolerance = 1e-6;
  const LmSummary summary = BundleAdjust(options, &s.problem).lm;
  EXPECT_EQ(summary.termination, TerminationReason::kGradientTolerance);
  EXPECT_EQ(summary.iterations, 0);
}

}  // namespace
}  // namespace dba
