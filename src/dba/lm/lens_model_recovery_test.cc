// Surveys made by the generator (`dba generate --model photo --camera-model
// NAME`) in the lens models with tangential, high-order and fisheye terms
// recover their intrinsics within the noise: each free parameter ends
// within 4σ of the truth, σ from the covariance σ²_px S⁺ of the camera-side
// unknowns at the optimum (S the undamped reduced camera matrix; its
// pseudo-inverse leaves out the gauge).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "dba/io/binary_problem.h"
#include "dba/lm/bundle_adjust.h"
#include "dba/rcs/form_rcs.h"
#include "dba/synthetic/uav_generator.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

struct Recovery {
  LensModel model;
  double field_of_view;  // 0: the generator's default
};

class LensModelRecoveryTest : public ::testing::TestWithParam<Recovery> {};

TEST_P(LensModelRecoveryTest, IntrinsicsAreRecoveredWithinTheNoise) {
  const Recovery& c = GetParam();
  const std::string name = Info(c.model).name;
  UavSurveyOptions o;
  o.model = CameraModel::kPhoto;
  o.camera_model = c.model;
  o.field_of_view = c.field_of_view;
  o.images = 48;
  o.features_per_image = 400;
  o.physical_cameras = 2;
  o.pixel_noise = 0.5;
  o.focal_perturbation = 0.02;
  o.seed = 5;
  const std::string dir = testing::FreshTempDir("recovery_" + name);
  GenerateUavSurvey(o, dir + "/survey.dba", dir + "/truth.dba", {});
  Problem p = ReadBinaryProblem(dir + "/survey.dba");
  const Problem truth = ReadBinaryProblem(dir + "/truth.dba");
  ASSERT_EQ(p.group_models, std::vector<LensModel>(2, c.model));
  const Problem start = p;

  LmOptions options;
  options.num_threads = 2;
  const BundleAdjustSummary summary = BundleAdjust(options, &p);
  EXPECT_NE(summary.lm.termination, TerminationReason::kMaxIterations) << name;
  EXPECT_NE(summary.lm.termination, TerminationReason::kLambdaTooLarge) << name;
  // At the noise floor: RMS sqrt(2F/n) = σ√2 sqrt(1 - unknowns / residuals).
  const double n = static_cast<double>(p.num_observations());
  const double unknowns = static_cast<double>(UnknownLayout(p).num_unknowns() + 3 * p.num_points());
  const double floor = o.pixel_noise * std::sqrt(2.0) * std::sqrt(1.0 - unknowns / (2 * n));
  EXPECT_NEAR(summary.lm.Rms(summary.lm.final_cost), floor, 0.05 * floor) << name;

  RcsSystem sys = RcsSystem::ForProblem(p);
  FormRcs(p, 0.0, DampingBounds{}, 2, &sys);
  // Jacobi-scaled first (radians, metres and pixels differ by orders of
  // magnitude), so that only the 7 directions of the similarity gauge are
  // dropped, not weakly determined ones.
  const Eigen::MatrixXd S = testing::DenseFromBsmc(sys.S);
  const Eigen::VectorXd scale = S.diagonal().cwiseSqrt().cwiseInverse();
  const testing::SymmetricEigen eig =
      testing::EigenOfSymmetric(scale.asDiagonal() * S * scale.asDiagonal());
  const Eigen::VectorXd& ev = eig.values;
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(ev.size());
  int gauge = 0;
  for (int j = 0; j < ev.size(); ++j) {
    if (ev[j] > 1e-9 * ev.maxCoeff()) {
      inv[j] = 1.0 / ev[j];
    } else {
      ++gauge;
    }
  }
  EXPECT_EQ(gauge, 7) << name;
  const Eigen::MatrixXd covariance =
      o.pixel_noise * o.pixel_noise * scale.asDiagonal() * eig.vectors *
      inv.asDiagonal() * eig.vectors.transpose() * scale.asDiagonal();
  int moved_far = 0;
  for (int64_t g = 0; g < p.num_groups(); ++g) {
    const int32_t row = sys.layout.intrinsics_row(g);
    ASSERT_GE(row, 0);
    const auto& index = sys.layout.intrinsics_free_index(g);
    for (int j = 0; j < sys.layout.block_size(row); ++j) {
      const int d = index[j];
      const int64_t at = sys.layout.row_offset(row) + j;
      const double sd = std::sqrt(covariance(at, at));
      const double got = p.intrinsics(g)[d], want = truth.intrinsics(g)[d];
      EXPECT_LT(std::abs(got - want), 4.0 * sd)
          << name << " group " << g << " " << LensModelParamName(c.model, d) << ": " << got
          << " vs " << want << " (σ " << sd << ")";
      if (std::abs(start.intrinsics(g)[d] - want) > 4.0 * sd) ++moved_far;
    }
  }
  // The focal lengths started outside that (a test that cannot fail is none).
  EXPECT_GE(moved_far, 1) << name;
}

INSTANTIATE_TEST_SUITE_P(
    Models, LensModelRecoveryTest,
    ::testing::Values(Recovery{LensModel::kOpenCV, 0.0}, Recovery{LensModel::kFullOpenCV, 100.0},
                      Recovery{LensModel::kOpenCVFisheye, 120.0},
                      Recovery{LensModel::kBrown, 90.0}),
    [](const ::testing::TestParamInfo<Recovery>& info) {
      return std::string(Info(info.param.model).name);
    });

}  // namespace
}  // namespace dba
