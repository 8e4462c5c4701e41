// Camera-centre priors in the RCS against the dense normal equations with
// the prior terms added to the camera blocks, under the squared loss and a
// robust one; and a solve with priors ends at the priors' frame.
#include "dba/lm/prior_workers.h"

#include <gtest/gtest.h>

#include <random>

#include "dba/lm/bundle_adjust.h"
#include "dba/lm/local_point_workers.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

testing::SyntheticProblem SmallSurvey(uint32_t seed) {
  testing::SyntheticPhotoOptions o;
  o.geometry.num_cameras = 8;
  o.geometry.num_points = 80;
  o.geometry.max_track = 5;
  o.geometry.pixel_noise = 0.5;
  o.geometry.rotation_perturbation = 0.01;
  o.geometry.translation_perturbation = 0.05;
  o.geometry.point_perturbation = 0.05;
  o.geometry.seed = seed;
  o.num_groups = 2;
  return testing::MakeSyntheticPhoto(o);
}

// Priors on every image but the last: the true centres, moved by up to a
// metre, σ (0.3, 0.3, 0.6).
CameraPriors PriorsOf(const Problem& truth, RobustLoss loss) {
  CameraPriors priors;
  priors.loss = loss;
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 0.3);
  for (int32_t i = 0; i + 1 < truth.num_images(); ++i) {
    CameraCentrePrior p;
    p.image = i;
    p.centre = CameraCentre(truth.camera(i)) + Vec3(n(rng), n(rng), n(rng));
    p.sigma = Vec3(0.3, 0.3, 0.6);
    priors.priors.push_back(p);
  }
  return priors;
}

TEST(PriorWorkers, RcsWithPriorsMatchesDenseNormalEquations) {
  for (const RobustLoss loss : {RobustLoss{}, RobustLoss{LossType::kCauchy, 1.0}}) {
    testing::SyntheticProblem s = SmallSurvey(1);
    Problem& problem = s.problem;
    problem.fixed_cameras.assign(problem.num_images(), 0);
    problem.fixed_cameras[2] = 1;  // a fixed camera's prior adds cost only
    const CameraPriors priors = PriorsOf(s.truth, loss);
    LocalPointWorkers points(&problem, DampingBounds{}, 2);
    std::vector<double> cameras = problem.cameras;
    PriorWorkers workers(&points, &cameras, problem, priors);
    const RcsSystem& sys = workers.FormRcs(0.0);

    auto dense = testing::BuildDenseNormalEquations(problem, 0.0, DampingBounds{});
    const UnknownLayout layout(problem);
    double prior_cost = 0.0;
    for (const CameraCentrePrior& p : priors.priors) {
      CentrePriorJacobian J;
      const Vec3 r = CentrePriorResidual(problem.camera(p.image), priors.lever_arm, p, &J);
      double rho[3];
      loss.Evaluate(r.squaredNorm(), rho);
      prior_cost += 0.5 * rho[0];
      const int32_t row = layout.camera_row(p.image);
      if (row < 0) continue;
      // Triggs's weight: ρ' I (+ 2ρ'' r rᵀ where ρ'' > 0).
      Eigen::Matrix3d w = rho[1] * Eigen::Matrix3d::Identity();
      if (rho[2] > 0) w += 2 * rho[2] * r * r.transpose();
      const int64_t o = layout.row_offset(row);
      dense.H.block<6, 6>(o, o) += J.transpose() * w * J;
      dense.g.segment<6>(o) += rho[1] * J.transpose() * r;
    }
    const Eigen::MatrixXd S = testing::DenseFromBsmc(sys.S);
    const Eigen::MatrixXd want = dense.ReducedCameraMatrix();
    EXPECT_LT((S - want).norm(), 1e-10 * want.norm());
    const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(sys.b.data(), sys.b.size());
    EXPECT_LT((b - dense.ReducedRhs()).norm(), 1e-10 * dense.ReducedRhs().norm());
    EXPECT_NEAR(sys.cost, dense.cost + prior_cost, 1e-12 * sys.cost);
    EXPECT_GT(prior_cost, 1.0);  // the priors do weigh
  }
}

// The antenna's lever arm as 3 unknowns: the RCS (with the lever arm's row
// last) against the observations' dense Schur complement plus JᵀJ and Jᵀr of
// the priors, J by central differences of the priors' residuals through
// UnknownLayout::Plus (every camera unknown and the lever arm's).
TEST(PriorWorkers, RcsWithARefinedLeverArmMatchesDenseNormalEquations) {
  testing::SyntheticProblem s = SmallSurvey(3);
  Problem& problem = s.problem;
  problem.fixed_cameras.assign(problem.num_images(), 0);
  problem.fixed_cameras[1] = 1;  // its prior still touches the lever arm
  CameraPriors priors = PriorsOf(s.truth, RobustLoss{});
  priors.lever_arm = Vec3(0.4, -0.3, 0.8);
  priors.refine_lever_arm = true;
  LocalPointWorkers points(&problem, DampingBounds{}, 2, RobustLoss{}, {}, false, true);
  std::vector<double> x = problem.cameras;
  x.insert(x.end(), {0.3, -0.2, 0.5});  // the lever arm's current value
  PriorWorkers workers(&points, &x, problem, priors);
  const RcsSystem& sys = workers.FormRcs(0.0);
  const UnknownLayout& layout = sys.layout;
  ASSERT_EQ(layout.lever_arm_row(), layout.num_block_rows() - 1);
  ASSERT_EQ(layout.block_size(layout.lever_arm_row()), 3);

  const int64_t n = layout.num_unknowns(), m = 3 * static_cast<int64_t>(priors.priors.size());
  auto residuals_at = [&](const std::vector<double>& at) {
    Eigen::VectorXd r(m);
    const Vec3 a(at.data() + problem.cameras.size());
    for (size_t k = 0; k < priors.priors.size(); ++k) {
      const CameraCentrePrior& p = priors.priors[k];
      r.segment<3>(3 * k) = CentrePriorResidual(at.data() + 6 * p.image, a, p, nullptr);
    }
    return r;
  };
  Eigen::MatrixXd J(m, n);
  for (int64_t j = 0; j < n; ++j) {
    std::vector<double> delta(n, 0.0), plus(x.size()), minus(x.size());
    const double h = 1e-6;
    delta[j] = h;
    layout.Plus(x.data(), delta.data(), plus.data());
    delta[j] = -h;
    layout.Plus(x.data(), delta.data(), minus.data());
    J.col(j) = (residuals_at(plus) - residuals_at(minus)) / (2 * h);
  }
  const Eigen::VectorXd r = residuals_at(x);
  auto dense = testing::BuildDenseNormalEquations(problem, 0.0, DampingBounds{});
  Eigen::MatrixXd want = Eigen::MatrixXd::Zero(n, n);
  const int64_t nc = dense.num_camera_params;
  ASSERT_EQ(nc + 3, n);
  want.topLeftCorner(nc, nc) = dense.ReducedCameraMatrix();
  want += J.transpose() * J;
  Eigen::VectorXd want_b = Eigen::VectorXd::Zero(n);
  want_b.head(nc) = dense.ReducedRhs();
  want_b -= J.transpose() * r;
  const Eigen::MatrixXd S = testing::DenseFromBsmc(sys.S);
  EXPECT_LT((S - want).norm(), 1e-7 * want.norm());
  EXPECT_LT((S.bottomRightCorner(3, 3) - (J.rightCols(3).transpose() * J.rightCols(3))).norm(),
            1e-7 * S.bottomRightCorner(3, 3).norm());
  EXPECT_GT(S.topRightCorner(nc, 3).norm(), 1e-3);  // the (camera, lever arm) blocks weigh
  const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(sys.b.data(), sys.b.size());
  EXPECT_LT((b - want_b).norm(), 1e-7 * want_b.norm());
  EXPECT_NEAR(sys.cost, dense.cost + 0.5 * r.squaredNorm(), 1e-12 * sys.cost);
}

// A solve from the lever arm's wrong start ends at least as low as one given
// the true lever arm (3 more unknowns), with the antennas on the priors. The
// ring of cameras all looking at its centre cannot place the lever arm
// itself (its forward part is the block's scale, its sideways part a turn
// about the ring's axis): tests/cli_rigs.sh recovers one from an aerial
// survey.
TEST(PriorWorkers, SolveWithARefinedLeverArmFitsTheAntennas) {
  testing::SyntheticProblem s = SmallSurvey(4);
  const Vec3 truth(0.4, -0.3, 0.8);
  CameraPriors priors = PriorsOf(s.truth, RobustLoss{});
  for (CameraCentrePrior& p : priors.priors) {
    p.centre = AntennaPosition(s.truth.camera(p.image), truth);
    p.sigma = Vec3(0.01, 0.01, 0.01);
  }
  LmOptions options;
  options.num_threads = 2;
  Problem given = s.problem;
  priors.lever_arm = truth;
  const BundleAdjustSummary at_truth = BundleAdjust(options, &given, {}, {}, &priors);
  const double given_priors_cost = CameraPriorsCost(priors, given);
  Problem refined = s.problem;
  priors.lever_arm = Vec3::Zero();
  priors.refine_lever_arm = true;
  const BundleAdjustSummary summary = BundleAdjust(options, &refined, {}, {}, &priors);
  EXPECT_LT(summary.lm.final_cost, at_truth.lm.final_cost * (1 + 1e-6));
  EXPECT_GT(summary.lm.final_cost, 0.98 * at_truth.lm.final_cost);
  EXPECT_GT(summary.lever_arm.norm(), 0.1);  // it moved from 0
  priors.lever_arm = summary.lever_arm;
  EXPECT_LT(CameraPriorsCost(priors, refined), given_priors_cost + 1.0);
  EXPECT_EQ(refined.cameras.size(), s.problem.cameras.size());  // the lever arm not in the problem
}

// The world moved by d: X + d, and each camera's t - R d (the same images).
void Shift(const Vec3& d, Problem* p) {
  for (int64_t i = 0; i < p->num_images(); ++i) {
    double* pose = p->camera(i);
    const Vec3 t = Vec3(pose[3], pose[4], pose[5]) -
                   AngleAxisToRotation(Vec3(pose[0], pose[1], pose[2])) * d;
    for (int k = 0; k < 3; ++k) pose[3 + k] = t[k];
  }
  for (int64_t k = 0; k < p->num_points(); ++k) {
    for (int a = 0; a < 3; ++a) p->point(k)[a] += d[a];
  }
}

double WorstCentreError(const Problem& p, const Problem& truth) {
  double worst = 0.0;
  for (int32_t i = 0; i < p.num_images(); ++i) {
    worst = std::max(worst, (CameraCentre(p.camera(i)) - CameraCentre(truth.camera(i))).norm());
  }
  return worst;
}

TEST(PriorWorkers, SolveWithPriorsLowersTheirCostAndHoldsTheFrame) {
  testing::SyntheticProblem s = SmallSurvey(2);
  const CameraPriors priors = PriorsOf(s.truth, RobustLoss{});
  // Started 3 m off in the world: the observations alone cannot tell.
  Problem problem = s.problem;
  Shift(Vec3(3.0, -1.0, 0.5), &problem);
  Problem without = problem;
  LmOptions options;
  options.num_threads = 2;
  const BundleAdjustSummary summary = BundleAdjust(options, &problem, {}, {}, &priors);
  EXPECT_NE(summary.lm.termination, TerminationReason::kMaxIterations);
  EXPECT_LT(summary.lm.final_cost, summary.lm.initial_cost);
  // The centres end near the truth in the truth's own frame (no alignment):
  // the priors fix the datum; without them the block stays where it was.
  EXPECT_LT(WorstCentreError(problem, s.truth), 0.5);
  BundleAdjust(options, &without);
  EXPECT_GT(WorstCentreError(without, s.truth), 2.5);
  // And the final cost is the observations' plus the priors'.
  const double prior_cost = CameraPriorsCost(priors, problem);
  EXPECT_GT(prior_cost, 0.0);
  EXPECT_LT(prior_cost, summary.lm.final_cost);
}

}  // namespace
}  // namespace dba
