// One-process bundle adjustment in the photogrammetric model: shared
// intrinsics are recovered within the noise, fixed parameters stay put, and
// the optimum reaches the noise floor.
#include "dba/lm/bundle_adjust.h"

#include <gtest/gtest.h>

#include <cmath>

#include "dba/testing/dense_reference.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

testing::SyntheticProblem SharedIntrinsicsProblem(double noise) {
  testing::SyntheticPhotoOptions o;
  o.geometry.num_cameras = 12;
  o.geometry.num_points = 250;
  o.geometry.max_track = 6;
  o.geometry.pixel_noise = noise;
  o.geometry.rotation_perturbation = 0.005;
  o.geometry.translation_perturbation = 0.02;
  o.geometry.point_perturbation = 0.02;
  o.geometry.seed = 11;
  o.num_groups = 2;
  o.focal_perturbation = 0.02;
  o.principal_perturbation = 5.0;
  o.distortion_perturbation = 0.02;
  return testing::MakeSyntheticPhoto(o);
}

TEST(BundleAdjust, SharedIntrinsicsAreRecoveredWithinTheNoise) {
  const double sigma = 0.5;
  testing::SyntheticProblem s = SharedIntrinsicsProblem(sigma);
  Problem& p = s.problem;
  LmOptions options;
  options.num_threads = 2;
  const BundleAdjustSummary summary = BundleAdjust(options, &p);
  EXPECT_NE(summary.lm.termination, TerminationReason::kMaxIterations);
  EXPECT_NE(summary.lm.termination, TerminationReason::kLambdaTooLarge);
  // 12 poses of 6 and 2 groups of 5 unknowns.
  EXPECT_EQ(summary.rcs.block_rows, 14);
  // RMS sqrt(2F/n) at the optimum is σ√2 sqrt(1 - unknowns / residuals).
  const double n = static_cast<double>(p.num_observations());
  const double unknowns = 12 * 6 + 2 * 5 + 3 * p.num_points();
  const double expected_rms = sigma * std::sqrt(2.0) * std::sqrt(1.0 - unknowns / (2 * n));
  EXPECT_NEAR(summary.lm.Rms(summary.lm.final_cost), expected_rms, 0.1 * expected_rms);
  // The intrinsics' standard deviations at the optimum: σ² (JᵀJ)⁺ (pseudo-
  // inverse: the gauge leaves JᵀJ singular; intrinsics do not depend on it).
  const auto dense = testing::BuildDenseNormalEquations(p, 0.0, DampingBounds{});
  const testing::SymmetricEigen eig = testing::EigenOfSymmetric(dense.H);
  const Eigen::VectorXd& ev = eig.values;
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(ev.size());
  for (int j = 0; j < ev.size(); ++j) inv[j] = ev[j] > 1e-10 * ev.maxCoeff() ? 1.0 / ev[j] : 0.0;
  const Eigen::MatrixXd covariance =
      sigma * sigma * eig.vectors * inv.asDiagonal() * eig.vectors.transpose();
  const UnknownLayout layout(p);
  const testing::SyntheticProblem start = SharedIntrinsicsProblem(sigma);
  for (int g = 0; g < 2; ++g) {
    const double* got = p.intrinsics(g);
    const double* truth = s.truth.intrinsics(g);
    const int64_t o = layout.row_offset(layout.intrinsics_row(g));
    for (int d = 0; d < 5; ++d) {
      const double sd = std::sqrt(covariance(o + d, o + d));
      EXPECT_LT(std::abs(got[d] - truth[d]), 4.0 * sd)
          << "group " << g << " parameter " << d << ": " << got[d] << " vs " << truth[d];
      // The focal length started far outside that (the principal point is
      // weakly determined in this narrow-field geometry: σ of several px).
      if (d == 0) {
        EXPECT_GT(std::abs(start.problem.intrinsics(g)[d] - truth[d]), 4.0 * sd) << d;
      }
    }
    EXPECT_NEAR(got[0], truth[0], 0.005 * truth[0]) << "f, group " << g;
  }
}

TEST(BundleAdjust, FixedParametersStayAtTheirValues) {
  testing::SyntheticProblem s = SharedIntrinsicsProblem(0.5);
  Problem& p = s.problem;
  p.fixed_cameras.assign(p.num_images(), 0);
  p.fixed_cameras[0] = p.fixed_cameras[5] = 1;
  p.fixed_intrinsics = {kIntrinsicCx | kIntrinsicCy, kAllIntrinsics};
  const Problem start = p;
  LmOptions options;
  options.num_threads = 2;
  const BundleAdjustSummary summary = BundleAdjust(options, &p);
  EXPECT_EQ(summary.rcs.block_rows, 10 + 1);
  EXPECT_LT(summary.lm.final_cost, 0.1 * summary.lm.initial_cost);
  for (int d = 0; d < 6; ++d) {
    EXPECT_EQ(p.camera(0)[d], start.camera(0)[d]);
    EXPECT_EQ(p.camera(5)[d], start.camera(5)[d]);
    EXPECT_NE(p.camera(1)[d], start.camera(1)[d]);
  }
  EXPECT_NE(p.intrinsics(0)[0], start.intrinsics(0)[0]);
  EXPECT_EQ(p.intrinsics(0)[1], start.intrinsics(0)[1]);  // cx fixed
  EXPECT_EQ(p.intrinsics(0)[2], start.intrinsics(0)[2]);  // cy fixed
  for (int d = 0; d < 5; ++d) EXPECT_EQ(p.intrinsics(1)[d], start.intrinsics(1)[d]);
}

TEST(BundleAdjust, PhotoModelOneAndTwoThreadsAgree) {
  testing::SyntheticProblem a = SharedIntrinsicsProblem(1.0), b = SharedIntrinsicsProblem(1.0);
  LmOptions options;
  options.num_threads = 1;
  const double cost1 = BundleAdjust(options, &a.problem).lm.final_cost;
  options.num_threads = 2;
  const double cost2 = BundleAdjust(options, &b.problem).lm.final_cost;
  EXPECT_NEAR(cost1, cost2, 1e-9 * cost1);
}

}  // namespace
}  // namespace dba
