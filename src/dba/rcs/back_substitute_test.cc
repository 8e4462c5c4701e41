// Back-substitution (paper eq. 5) and the step's costs against the dense
// solution of the full damped normal equations.
#include "dba/rcs/back_substitute.h"

#include <gtest/gtest.h>

#include "dba/camera/bal_camera.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/synthetic_bal.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

// ½ Σ ρ(|r|²) of a BAL problem at the given cameras and points, directly.
double CandidateCost(const Problem& problem, const std::vector<double>& cameras,
                     const std::vector<double>& points, const RobustLoss& loss = RobustLoss()) {
  double cost = 0.0;
  for (int64_t k = 0; k < problem.num_points(); ++k) {
    for (int64_t obs = problem.point_offsets[k]; obs < problem.point_offsets[k + 1]; ++obs) {
      cost += 0.5 * loss.Rho(BalResidual(cameras.data() + 9 * problem.obs_camera[obs],
                                         points.data() + 3 * k, problem.pixel(obs))
                                 .squaredNorm());
    }
  }
  return cost;
}

// A small perturbed BAL problem (6 cameras, 50 points).
Problem SmallProblem() {
  testing::SyntheticBalOptions o;
  o.num_cameras = 6;
  o.num_points = 50;
  o.pixel_noise = 0.5;
  o.rotation_perturbation = 0.01;
  o.point_perturbation = 0.05;
  return testing::MakeSyntheticBal(o).problem;
}

TEST(BackSubstitute, RecoversTheFullNewtonStepAndItsCosts) {
  const Problem problem = SmallProblem();
  const double lambda = 0.3;
  const DampingBounds bounds;
  const auto dense = testing::BuildDenseNormalEquations(problem, lambda, bounds);
  const Eigen::VectorXd step = dense.SolveStep();
  const int nc = dense.num_camera_params;

  std::vector<double> delta_c(step.data(), step.data() + nc);
  std::vector<double> candidate_cameras = problem.cameras;
  UnknownLayout(problem).Plus(problem.cameras.data(), delta_c.data(), candidate_cameras.data());
  std::vector<double> candidate_points;
  const StepEvaluation e = BackSubstitute(problem, UnknownLayout(problem), lambda, bounds, delta_c,
                                          candidate_cameras, 2, &candidate_points);

  // δX from eq. 5 equals the point part of the full solution.
  const Eigen::VectorXd dX = step.tail(step.size() - nc);
  for (int64_t j = 0; j < dX.size(); ++j) {
    EXPECT_NEAR(candidate_points[j] - problem.points[j], dX[j],
                1e-9 * (1 + dX.cwiseAbs().maxCoeff()));
  }
  // Model cost ½|r + J δ|² and the true cost at x + δ.
  const double model = 0.5 * (dense.r + dense.J * step).squaredNorm();
  EXPECT_NEAR(e.model_cost, model, 1e-10 * dense.cost);
  const double candidate = CandidateCost(problem, candidate_cameras, candidate_points);
  EXPECT_NEAR(e.candidate_cost, candidate, 1e-12 * candidate);
  EXPECT_NEAR(e.point_step_squared_norm, dX.squaredNorm(), 1e-9 * dX.squaredNorm());
  // The current points' spread about their centroid.
  const auto X = Eigen::Map<const Eigen::Matrix3Xd>(problem.points.data(), 3,
                                                    problem.num_points());
  const Vec3 centroid = X.rowwise().mean();
  const double m2 = (X.colwise() - centroid).squaredNorm();
  EXPECT_EQ(e.point_spread.count, static_cast<double>(problem.num_points()));
  EXPECT_LE((e.point_spread.mean - centroid).norm(), 1e-12 * centroid.norm());
  EXPECT_NEAR(e.point_spread.m2, m2, 1e-12 * m2);
}


// The photogrammetric model with a fixed image and a fixed principal point:
// δX and the costs against the dense solution over the free unknowns.
TEST(BackSubstitute, PhotoModelWithFixedParameters) {
  testing::SyntheticPhotoOptions o;
  o.geometry.num_cameras = 6;
  o.geometry.num_points = 50;
  o.geometry.pixel_noise = 0.5;
  o.geometry.rotation_perturbation = 0.01;
  o.geometry.point_perturbation = 0.05;
  o.num_groups = 2;
  o.focal_perturbation = 0.01;
  o.distortion_perturbation = 0.01;
  Problem problem = testing::MakeSyntheticPhoto(o).problem;
  problem.fixed_cameras = {0, 0, 1, 0, 0, 0};
  problem.fixed_intrinsics = {kIntrinsicCx | kIntrinsicCy, 0};
  const double lambda = 0.3;
  const DampingBounds bounds;
  const auto dense = testing::BuildDenseNormalEquations(problem, lambda, bounds);
  const Eigen::VectorXd step = dense.SolveStep();
  const int nc = dense.num_camera_params;
  const UnknownLayout layout(problem);
  ASSERT_EQ(layout.num_unknowns(), nc);
  ASSERT_EQ(nc, 5 * 6 + 3 + 5);

  std::vector<double> delta_c(step.data(), step.data() + nc);
  std::vector<double> candidate_cameras(problem.cameras.size());
  layout.Plus(problem.cameras.data(), delta_c.data(), candidate_cameras.data());
  // Fixed parameters do not move.
  for (int d = 0; d < 6; ++d) EXPECT_EQ(candidate_cameras[6 * 2 + d], problem.camera(2)[d]);
  const int64_t g0 = 6 * 6;
  EXPECT_EQ(candidate_cameras[g0 + 1], problem.cameras[g0 + 1]);
  EXPECT_EQ(candidate_cameras[g0 + 2], problem.cameras[g0 + 2]);
  EXPECT_NE(candidate_cameras[g0 + 3], problem.cameras[g0 + 3]);
  std::vector<double> candidate_points;
  const StepEvaluation e = BackSubstitute(problem, layout, lambda, bounds, delta_c,
                                          candidate_cameras, 2, &candidate_points);
  const Eigen::VectorXd dX = step.tail(step.size() - nc);
  for (int64_t j = 0; j < dX.size(); ++j) {
    EXPECT_NEAR(candidate_points[j] - problem.points[j], dX[j],
                1e-9 * (1 + dX.cwiseAbs().maxCoeff()));
  }
  const double model = 0.5 * (dense.r + dense.J * step).squaredNorm();
  EXPECT_NEAR(e.model_cost, model, 1e-10 * dense.cost);
  Problem moved = problem;
  moved.cameras = candidate_cameras;
  moved.points = candidate_points;
  const double candidate = testing::BuildDenseNormalEquations(moved, 0.0, bounds).cost;
  EXPECT_NEAR(e.candidate_cost, candidate, 1e-12 * candidate);
}

// With a robust loss: the model cost is Triggs's second-order model of the
// robust cost, ½ Σ ρ + gᵀδ + ½ δᵀ (Σ Jᵀ Ω J) δ (undamped), and the candidate
// cost ½ Σ ρ(|r(x + δ)|²).
TEST(BackSubstitute, RobustModelAndCandidateCosts) {
  Problem problem = SmallProblem();
  for (int64_t a = 0; a < problem.num_observations(); a += 4) problem.obs_pixel[2 * a] += 12.0;
  const RobustLoss loss{LossType::kCauchy, 1.0};
  const double lambda = 0.3;
  const DampingBounds bounds;
  const auto dense = testing::BuildDenseNormalEquations(problem, lambda, bounds, loss);
  const Eigen::VectorXd step = dense.SolveStep();
  const auto undamped = testing::BuildDenseNormalEquations(problem, 0.0, bounds, loss);
  const int nc = dense.num_camera_params;
  std::vector<double> delta_c(step.data(), step.data() + nc);
  std::vector<double> candidate_cameras = problem.cameras;
  UnknownLayout(problem).Plus(problem.cameras.data(), delta_c.data(), candidate_cameras.data());
  std::vector<double> candidate_points;
  const StepEvaluation e = BackSubstitute(problem, UnknownLayout(problem), lambda, bounds, delta_c,
                                          candidate_cameras, 2, &candidate_points, loss);
  const Eigen::VectorXd dX = step.tail(step.size() - nc);
  for (int64_t j = 0; j < dX.size(); ++j) {
    EXPECT_NEAR(candidate_points[j] - problem.points[j], dX[j],
                1e-9 * (1 + dX.cwiseAbs().maxCoeff()));
  }
  const double model = dense.cost + undamped.g.dot(step) + 0.5 * step.dot(undamped.H * step);
  EXPECT_NEAR(e.model_cost, model, 1e-10 * dense.cost);
  EXPECT_LT(e.model_cost, dense.cost);
  const double candidate =
      CandidateCost(problem, candidate_cameras, candidate_points, loss);
  EXPECT_NEAR(e.candidate_cost, candidate, 1e-12 * candidate);
}

}  // namespace
}  // namespace dba
