// The robust losses against finite differences of themselves, and the Triggs
// correction against the robust cost of a real observation: the corrected
// residual and Jacobian give the gradient of ½ ρ(|r|²) (by central
// differences) and the Gauss-Newton matrix Jᵀ (ρ' I + 2 ρ'' r rᵀ) J.
#include "dba/rcs/robust_loss.h"

#include "dba/camera/pose_step.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace dba {
namespace {

const LossType kAllLosses[] = {LossType::kTrivial, LossType::kHuber, LossType::kSoftL1,
                               LossType::kCauchy, LossType::kArctan, LossType::kTukey};

class RobustLossTest : public ::testing::TestWithParam<LossType> {};

TEST_P(RobustLossTest, DerivativesMatchFiniteDifferences) {
  const RobustLoss loss{GetParam(), 2.0};
  // Inside and outside the scale (b = 4), away from Huber's and Tukey's kink.
  for (double s : {0.01, 0.5, 3.0, 5.0, 40.0, 900.0}) {
    double rho[3], plus[3], minus[3];
    loss.Evaluate(s, rho);
    const double h = 1e-6 * std::max(1.0, s);
    loss.Evaluate(s + h, plus);
    loss.Evaluate(s - h, minus);
    EXPECT_NEAR(rho[1], (plus[0] - minus[0]) / (2 * h), 1e-6 * std::max(1.0, std::abs(rho[1])))
        << LossName(loss.type) << " s " << s;
    EXPECT_NEAR(rho[2], (plus[1] - minus[1]) / (2 * h), 1e-5 * std::max(1.0, std::abs(rho[2])))
        << LossName(loss.type) << " s " << s;
    EXPECT_EQ(loss.Rho(s), rho[0]);
    EXPECT_GE(rho[1], 0.0);
  }
  double at_zero[3];
  loss.Evaluate(0.0, at_zero);
  EXPECT_EQ(at_zero[0], 0.0) << LossName(loss.type);
  EXPECT_NEAR(at_zero[1], 1.0, 1e-12) << LossName(loss.type);  // quadratic near 0
}

TEST_P(RobustLossTest, ScaledAsCeresDefinesIt) {
  const RobustLoss loss{GetParam(), 3.0};
  const double s = 20.0, a = 3.0, b = 9.0;
  double expected = s;
  switch (loss.type) {
    case LossType::kTrivial: expected = s; break;
    case LossType::kHuber: expected = 2 * a * std::sqrt(s) - b; break;
    case LossType::kSoftL1: expected = 2 * b * (std::sqrt(1 + s / b) - 1); break;
    case LossType::kCauchy: expected = b * std::log(1 + s / b); break;
    case LossType::kArctan: expected = a * std::atan2(s, a); break;
    case LossType::kTukey: expected = b / 3; break;
  }
  EXPECT_NEAR(loss.Rho(s), expected, 1e-12 * expected) << LossName(loss.type);
}

// ½ ρ(|r(x)|²) for a BAL observation, x = the camera's 9 parameters.
double RobustCost(const RobustLoss& loss, const double* camera, const double* point,
                  const double* observed) {
  return 0.5 * loss.Rho(BalResidual(camera, point, observed).squaredNorm());
}

TEST_P(RobustLossTest, CorrectedPairGivesTheRobustGradientAndGaussNewtonMatrix) {
  const RobustLoss loss{GetParam(), 1.5};
  const double camera[9] = {0.1, -0.2, 0.05, 0.3, -0.1, -8.0, 500.0, 1e-3, -1e-6};
  const double point[3] = {0.4, -0.3, 1.0};
  const Vec2 projected = BalResidual(camera, point, std::vector<double>{0.0, 0.0}.data());
  // Residual norms from well inside to far outside the scale.
  for (double offset : {0.3, 1.2, 2.5, 9.0}) {
    const double observed[2] = {projected.x() - 0.6 * offset, projected.y() - 0.8 * offset};
    BalCameraJacobian J;
    PointJacobian J_p;
    const Vec2 r = BalResidualAndJacobians(camera, point, observed, &J, &J_p);
    const double s = r.squaredNorm();
    double rho[3];
    loss.Evaluate(s, rho);
    const LossCorrection correction(s, rho);
    BalCameraJacobian J_corrected = J;
    correction.CorrectJacobian(r, &J_corrected);
    const Vec2 r_corrected = correction.Residual(r);
    // Gradient of the robust cost against central differences.
    const Eigen::Matrix<double, 9, 1> gradient = J_corrected.transpose() * r_corrected;
    for (int p = 0; p < 9; ++p) {
      // The pose's columns are on its step (camera/pose_step.h).
      double plus[9], minus[9];
      std::copy(camera, camera + 9, plus);
      std::copy(camera, camera + 9, minus);
      const double h = 1e-6 * std::max(1e-3, p < kPoseSize ? 1.0 : std::abs(camera[p]));
      if (p < kPoseSize) {
        double step[kPoseSize] = {};
        step[p] = h;
        PlusPose(camera, step, plus);
        step[p] = -h;
        PlusPose(camera, step, minus);
      } else {
        plus[p] += h;
        minus[p] -= h;
      }
      const double numeric =
          (RobustCost(loss, plus, point, observed) - RobustCost(loss, minus, point, observed)) /
          (2 * h);
      EXPECT_NEAR(gradient[p], numeric, 1e-5 * std::max(1.0, std::abs(numeric)))
          << LossName(loss.type) << " |r| " << std::sqrt(s) << " parameter " << p;
    }
    // The Gauss-Newton matrix of the corrected pair.
    Eigen::Matrix2d omega = rho[1] * Eigen::Matrix2d::Identity();
    if (rho[2] > 0) omega += 2 * rho[2] * r * r.transpose();
    const Eigen::Matrix<double, 9, 9> expected = J.transpose() * omega * J;
    const Eigen::Matrix<double, 9, 9> actual = J_corrected.transpose() * J_corrected;
    EXPECT_LT((actual - expected).norm(), 1e-10 * std::max(1.0, expected.norm()))
        << LossName(loss.type) << " |r| " << std::sqrt(s);
  }
}

INSTANTIATE_TEST_SUITE_P(Losses, RobustLossTest, ::testing::ValuesIn(kAllLosses),
                         [](const ::testing::TestParamInfo<LossType>& info) {
                           return std::string(LossName(info.param));
                         });

// The branch no standard loss reaches (ρ'' > 0): the corrected pair still
// gives ρ' Jᵀ r and Jᵀ (ρ' I + 2 ρ'' r rᵀ) J.
TEST(LossCorrection, PositiveCurvatureKeepsTheSecondOrderTerm) {
  const Vec2 r(1.5, -0.7);
  Eigen::Matrix<double, 2, 4> J;
  J << 1, 2, -1, 0.5, 0.3, -2, 4, 1;
  const double s = r.squaredNorm(), rho[3] = {0.0, 0.8, 0.25};
  const LossCorrection correction(s, rho);
  Eigen::Matrix<double, 2, 4> J_corrected = J;
  correction.CorrectJacobian(r, &J_corrected);
  const Vec2 r_corrected = correction.Residual(r);
  EXPECT_LT((J_corrected.transpose() * r_corrected - rho[1] * J.transpose() * r).norm(), 1e-12);
  const Eigen::Matrix2d omega = rho[1] * Eigen::Matrix2d::Identity() + 2 * rho[2] * r * r.transpose();
  EXPECT_LT((J_corrected.transpose() * J_corrected - J.transpose() * omega * J).norm(), 1e-12);
}

TEST(RobustLoss, ParsesEveryNameItPrints) {
  for (LossType t : kAllLosses) {
    LossType parsed = LossType::kTrivial;
    EXPECT_TRUE(ParseLoss(LossName(t), &parsed));
    EXPECT_EQ(parsed, t);
  }
  LossType unused;
  EXPECT_FALSE(ParseLoss("l2", &unused));
}

}  // namespace
}  // namespace dba
