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
    PriorWorkers workers(&points, &cameras, kPhotoPoseSize, priors);
    const RcsSystem& sys = workers.FormRcs(0.0);

    auto dense = testing::BuildDenseNormalEquations(problem, 0.0, DampingBounds{});
    const UnknownLayout layout(problem);
    double prior_cost = 0.0;
    for (const CameraCentrePrior& p : priors.priors) {
      CentrePriorJacobian J;
      const Vec3 r = CentrePriorResidual(problem.camera(p.image), p, &J);
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
  const double prior_cost = CameraPriorsCost(priors, problem.cameras, kPhotoPoseSize);
  EXPECT_GT(prior_cost, 0.0);
  EXPECT_LT(prior_cost, summary.lm.final_cost);
}

}  // namespace
}  // namespace dba
