// Control points (points with a prior on their coordinates, problem.h's
// PointPrior) in the kernels: the RCS and its right-hand side, the
// back-substituted step and its costs, against the dense normal equations
// whose Jacobian carries the priors' rows w ∘ (X - X₀); and the priors
// following their points into a rank's share and through outlier rejection.
#include <gtest/gtest.h>

#include "dba/cluster/rank_share.h"
#include "dba/lm/outlier_rejection.h"
#include "dba/rcs/back_substitute.h"
#include "dba/rcs/form_rcs.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/synthetic_bal.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

double RelativeError(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / b.norm();
}

// Every 5th point becomes a control point, surveyed 3 cm (xy) and 6 cm (z)
// away from where it is, σ 2 cm / 5 cm.
void AddControlPoints(Problem* p) {
  for (int64_t k = 0; k < p->num_points(); k += 5) {
    PointPrior prior;
    prior.point = k;
    for (int a = 0; a < 3; ++a) {
      prior.position[a] = p->point(k)[a] + (a < 2 ? 0.03 : -0.06);
      prior.weight[a] = 1.0 / (a < 2 ? 0.02 : 0.05);
    }
    p->point_priors.push_back(prior);
  }
}

Problem BalProblem() {
  testing::SyntheticBalOptions o;
  o.num_cameras = 7;
  o.num_points = 60;
  o.max_track = 5;
  o.pixel_noise = 1.0;
  o.rotation_perturbation = 0.01;
  o.translation_perturbation = 0.05;
  o.point_perturbation = 0.05;
  o.seed = 3;
  Problem p = testing::MakeSyntheticBal(o).problem;
  AddControlPoints(&p);
  return p;
}

Problem PhotoProblem() {
  testing::SyntheticPhotoOptions o;
  o.geometry.num_cameras = 7;
  o.geometry.num_points = 60;
  o.geometry.max_track = 5;
  o.geometry.pixel_noise = 1.0;
  o.geometry.rotation_perturbation = 0.01;
  o.geometry.translation_perturbation = 0.05;
  o.geometry.point_perturbation = 0.05;
  o.num_groups = 2;
  o.focal_perturbation = 0.01;
  o.distortion_perturbation = 0.05;
  Problem p = testing::MakeSyntheticPhoto(o).problem;
  p.fixed_cameras.assign(p.num_images(), 0);
  p.fixed_cameras[1] = 1;
  AddControlPoints(&p);
  return p;
}

class ControlPointsTest : public ::testing::TestWithParam<bool> {
 protected:
  Problem MakeProblem() const { return GetParam() ? PhotoProblem() : BalProblem(); }
};

TEST_P(ControlPointsTest, RcsMatchesDenseNormalEquations) {
  const Problem problem = MakeProblem();
  ASSERT_EQ(problem.point_priors.size(), 12u);
  for (double lambda : {1e-4, 1.0}) {
    const DampingBounds bounds;
    RcsSystem sys = RcsSystem::ForProblem(problem);
    FormRcs(problem, lambda, bounds, 2, &sys);
    DampCameraBlocks(lambda, bounds, sys.camera_side_jtj_diagonal, &sys.S);
    const auto dense = testing::BuildDenseNormalEquations(problem, lambda, bounds);
    EXPECT_LT(RelativeError(testing::DenseFromBsmc(sys.S), dense.ReducedCameraMatrix()), 1e-10);
    const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(sys.b.data(), sys.b.size());
    EXPECT_LT(RelativeError(b, dense.ReducedRhs()), 1e-10);
    EXPECT_NEAR(sys.cost, dense.cost, 1e-12 * dense.cost);
    // The priors are a real part of the cost here (3 cm off at σ 2 cm).
    Problem without = problem;
    without.point_priors.clear();
    EXPECT_GT(dense.cost - testing::BuildDenseNormalEquations(without, lambda, bounds).cost,
              12 * 0.5 * (2 * 1.5 * 1.5 + 1.2 * 1.2) - 1e-9);
  }
}

TEST_P(ControlPointsTest, BackSubstitutionRecoversTheFullStepAndItsCosts) {
  const Problem problem = MakeProblem();
  const double lambda = 0.3;
  const DampingBounds bounds;
  const auto dense = testing::BuildDenseNormalEquations(problem, lambda, bounds);
  const Eigen::VectorXd step = dense.SolveStep();
  const int nc = dense.num_camera_params;
  const UnknownLayout layout(problem);
  std::vector<double> delta_c(step.data(), step.data() + nc);
  std::vector<double> candidate_cameras(problem.cameras.size());
  layout.Plus(problem.cameras.data(), delta_c.data(), candidate_cameras.data());
  std::vector<double> candidate_points;
  const StepEvaluation e = BackSubstitute(problem, layout, lambda, bounds, delta_c,
                                          candidate_cameras, 2, &candidate_points);
  const Eigen::VectorXd dX = step.tail(step.size() - nc);
  for (int64_t j = 0; j < dX.size(); ++j) {
    EXPECT_NEAR(candidate_points[j] - problem.points[j], dX[j],
                1e-9 * (1 + dX.cwiseAbs().maxCoeff()));
  }
  EXPECT_NEAR(e.model_cost, 0.5 * (dense.r + dense.J * step).squaredNorm(), 1e-10 * dense.cost);
  Problem moved = problem;
  moved.cameras = candidate_cameras;
  moved.points = candidate_points;
  const double candidate = testing::BuildDenseNormalEquations(moved, 0.0, bounds).cost;
  EXPECT_NEAR(e.candidate_cost, candidate, 1e-12 * candidate);
}

INSTANTIATE_TEST_SUITE_P(Models, ControlPointsTest, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "photo" : "bal"; });

TEST(ControlPoints, ShareKeepsItsPointsPriorsInLocalNumbering) {
  const Problem full = BalProblem();
  std::vector<int32_t> group(full.num_points());
  for (int64_t k = 0; k < full.num_points(); ++k) group[k] = static_cast<int32_t>(k % 3 == 1);
  const RankShare share = ExtractShare(full, group, 1);
  // Points 10, 25, 40 and 55 are control points with k % 3 == 1.
  ASSERT_EQ(share.problem.point_priors.size(), 4u);
  for (const PointPrior& p : share.problem.point_priors) {
    const int64_t k = share.global_point[p.point];
    EXPECT_EQ(k % 5, 0);
    EXPECT_EQ(p.position[0], full.point_prior(k)->position[0]);
  }
}

TEST(ControlPoints, OutlierRejectionKeepsThemAndRenumbersTheirPriors) {
  Problem problem = BalProblem();
  // Point 5 (a control point) and point 6 lose all but one observation.
  for (int64_t k : {5, 6}) {
    for (int64_t o = problem.point_offsets[k] + 1; o < problem.point_offsets[k + 1]; ++o) {
      problem.obs_pixel[2 * o] += 1e4;
    }
  }
  OriginalIndices original = OriginalIndices::Identity(problem);
  const RejectionRound round = DropOutliers({1e3, 0.0}, 2, &problem, &original);
  EXPECT_EQ(round.points_dropped, 1);  // point 6 only
  EXPECT_EQ(original.point[5], 5);
  EXPECT_EQ(original.point[6], 7);
  EXPECT_EQ(problem.point_offsets[6] - problem.point_offsets[5], 1);
  ASSERT_EQ(problem.point_priors.size(), 12u);
  for (size_t x = 0; x < problem.point_priors.size(); ++x) {
    EXPECT_EQ(original.point[problem.point_priors[x].point], static_cast<int64_t>(5 * x));
  }
}

}  // namespace
}  // namespace dba
