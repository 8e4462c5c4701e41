// Back-substitution (paper eq. 5) and the step's costs against the dense
// solution of the full damped normal equations.
#include "dba/rcs/back_substitute.h"

#include <gtest/gtest.h>

#include "dba/camera/bal_camera.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/synthetic_bal.h"

namespace dba {
namespace {

TEST(BackSubstitute, RecoversTheFullNewtonStepAndItsCosts) {
  testing::SyntheticBalOptions o;
  o.num_cameras = 6;
  o.num_points = 50;
  o.pixel_noise = 0.5;
  o.rotation_perturbation = 0.01;
  o.point_perturbation = 0.05;
  const BalProblem problem = testing::MakeSyntheticBal(o).problem;
  const double lambda = 0.3;
  const DampingBounds bounds;
  const auto dense = testing::BuildDenseNormalEquations(problem, lambda, bounds);
  const Eigen::VectorXd step = dense.SolveStep();
  const int nc = dense.num_camera_params;

  std::vector<double> delta_c(step.data(), step.data() + nc);
  std::vector<double> candidate_cameras = problem.cameras;
  for (int i = 0; i < nc; ++i) candidate_cameras[i] += delta_c[i];
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
  double candidate = 0.0;
  for (int64_t k = 0; k < problem.num_points(); ++k) {
    for (int64_t obs = problem.point_offsets[k]; obs < problem.point_offsets[k + 1]; ++obs) {
      candidate += 0.5 * BalResidual(candidate_cameras.data() + 9 * problem.obs_camera[obs],
                                     candidate_points.data() + 3 * k, problem.pixel(obs))
                             .squaredNorm();
    }
  }
  EXPECT_NEAR(e.candidate_cost, candidate, 1e-12 * candidate);
  EXPECT_NEAR(e.point_step_squared_norm, dX.squaredNorm(), 1e-9 * dX.squaredNorm());
  const Eigen::VectorXd X = Eigen::Map<const Eigen::VectorXd>(problem.points.data(),
                                                              problem.points.size());
  EXPECT_NEAR(e.point_squared_norm, X.squaredNorm(), 1e-12 * X.squaredNorm());
}

}  // namespace
}  // namespace dba
