// Analytic Jacobians of the photogrammetric camera against central
// differences in every lens model, and its agreement with the BAL model it
// generalizes.
#include "dba/camera/photo_camera.h"
#include "dba/camera/bal_camera.h"
#include "dba/camera/typical_lens.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <vector>

namespace dba {
namespace {

struct Sample {
  double pose[6];
  std::vector<double> intrinsics;
  double point[3];
  double observed[2];
};

// A camera-frame point at up to `max_angle` (radians) off the axis (for
// EQUIRECTANGULAR: any azimuth up to 150°, elevation up to 60°), placed in
// the world through a random pose.
Sample RandomSample(std::mt19937& rng, LensModel m, double rotation_scale, double max_angle) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Sample s;
  for (int i = 0; i < 3; ++i) s.pose[i] = rotation_scale * u(rng);
  const Mat3 R = AngleAxisToRotation(Vec3(s.pose[0], s.pose[1], s.pose[2]));
  Vec3 P;
  const double depth = 3.0 + 2.0 * std::abs(u(rng));
  if (m == LensModel::kEquirectangular) {
    const double azimuth = 2.6 * u(rng), elevation = 1.0 * u(rng);
    P = depth * Vec3(std::cos(elevation) * std::sin(azimuth), -std::sin(elevation),
                     std::cos(elevation) * std::cos(azimuth));
  } else {
    const double angle = max_angle * std::abs(u(rng)), direction = 3.2 * u(rng);
    P = depth * Vec3(std::sin(angle) * std::cos(direction), std::sin(angle) * std::sin(direction),
                     std::cos(angle));
  }
  const Vec3 X(5 * u(rng), 5 * u(rng), 5 * u(rng));
  const Vec3 t = P - R * X;
  for (int i = 0; i < 3; ++i) s.pose[3 + i] = t[i], s.point[i] = X[i];
  s.intrinsics = TypicalLensParams(m, 1000 + 200 * u(rng), 1280, 960);
  for (size_t j = 0; j < s.intrinsics.size(); ++j) s.intrinsics[j] *= 1.0 + 0.1 * u(rng);
  s.observed[0] = 600 + 50 * u(rng);
  s.observed[1] = 500 + 50 * u(rng);
  return s;
}

void ExpectJacobiansMatch(LensModel m, Sample s, const std::string& where) {
  PoseJacobian J_pose;
  IntrinsicsJacobian J_intr;
  PointJacobian J_point;
  const Vec2 r0 = PhotoResidualAndJacobians(m, s.pose, s.intrinsics.data(), s.point, s.observed,
                                            &J_pose, &J_intr, &J_point);
  EXPECT_LT((r0 - PhotoResidual(m, s.pose, s.intrinsics.data(), s.point, s.observed)).norm(),
            1e-12);
  const int n = LensModelParams(m);
  const uint16_t unknown = LensModelParamMask(m);
  for (int j = 0; j < 9 + n; ++j) {
    if (j >= 6 && j < 6 + n && !(unknown & (1u << (j - 6)))) continue;  // metadata
    // The pose's columns are on its step (camera/pose_step.h), the others on
    // the parameters.
    auto residual_at = [&](double h) {
      Sample moved = s;
      if (j < kPoseSize) {
        double delta[kPoseSize] = {};
        delta[j] = h;
        PlusPose(s.pose, delta, moved.pose);
      } else {
        (j < 6 + n ? moved.intrinsics[j - 6] : moved.point[j - 6 - n]) += h;
      }
      return PhotoResidual(m, moved.pose, moved.intrinsics.data(), moved.point, moved.observed);
    };
    const double x0 = j < kPoseSize ? 0.0 : j < 6 + n ? s.intrinsics[j - 6] : s.point[j - 6 - n];
    const double h = 1e-6 * std::max(1.0, std::abs(x0));
    const Vec2 numeric = (residual_at(h) - residual_at(-h)) / (2 * h);
    const Vec2 analytic = j < 6       ? Vec2(J_pose.col(j))
                          : j < 6 + n ? Vec2(J_intr.col(j - 6))
                                      : Vec2(J_point.col(j - 6 - n));
    EXPECT_LT((numeric - analytic).norm(), 1e-5 * (1.0 + analytic.norm()))
        << Info(m).name << " " << where << " parameter " << j << " analytic "
        << analytic.transpose() << " numeric " << numeric.transpose();
  }
}

TEST(PhotoCamera, JacobiansMatchCentralDifferencesInEveryLensModel) {
  for (const LensModelInfo& info : LensModels()) {
    const LensModel m = info.id;
    std::mt19937 rng(3 + static_cast<int>(m));
    // Wide angles for the models made for them, a normal lens's otherwise.
    const bool wide = m == LensModel::kOpenCVFisheye || m == LensModel::kSimpleRadialFisheye ||
                      m == LensModel::kRadialFisheye || m == LensModel::kThinPrismFisheye ||
                      m == LensModel::kRadTanThinPrismFisheye || m == LensModel::kSimpleFisheye ||
                      m == LensModel::kFisheye || m == LensModel::kFov || m == LensModel::kEucm;
    for (int trial = 0; trial < 200; ++trial) {
      // Every fifth point within 0.3° of the axis (FOV's small-radius series).
      const double angle = trial % 5 == 0 ? 0.005 : wide ? 1.3 : 0.6;
      ExpectJacobiansMatch(m, RandomSample(rng, m, trial % 4 == 0 ? 1e-7 : 2.0, angle),
                           "trial " + std::to_string(trial));
    }
  }
}

// FOV with ω² < 1e-4: COLMAP's series branch.
TEST(PhotoCamera, FovJacobiansMatchInItsSmallOmegaBranch) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    Sample s = RandomSample(rng, LensModel::kFov, 2.0, 0.8);
    s.intrinsics[4] = 0.006;
    ExpectJacobiansMatch(LensModel::kFov, s, "trial " + std::to_string(trial));
  }
}

// COLMAP -> BAL (data/README.md): R_bal = diag(1,-1,-1) R, t_bal = diag(1,-1,-1) t,
// x_bal = x - cx, y_bal = -(y - cy). Both models give the same residual up
// to the sign of y.
TEST(PhotoCamera, AgreesWithTheBalModelUnderTheColmapMapping) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 100; ++trial) {
    Sample s = RandomSample(rng, LensModel::kRadial, 2.0, 0.6);
    const double* k = s.intrinsics.data();
    const Mat3 flip = Vec3(1, -1, -1).asDiagonal();
    const Mat3 R_bal = flip * AngleAxisToRotation(Vec3(s.pose[0], s.pose[1], s.pose[2]));
    const Eigen::AngleAxisd aa(R_bal);
    const Vec3 omega_bal = aa.angle() * aa.axis();
    const Vec3 t_bal = flip * Vec3(s.pose[3], s.pose[4], s.pose[5]);
    const double bal[9] = {omega_bal[0], omega_bal[1], omega_bal[2], t_bal[0], t_bal[1],
                           t_bal[2], k[0], k[3], k[4]};
    const double observed_bal[2] = {s.observed[0] - k[1], -(s.observed[1] - k[2])};
    const Vec2 r = PhotoResidual(LensModel::kRadial, s.pose, k, s.point, s.observed);
    const Vec2 r_bal = BalResidual(bal, s.point, observed_bal);
    EXPECT_NEAR(r_bal.x(), r.x(), 1e-8 * (1 + r.norm()));
    EXPECT_NEAR(r_bal.y(), -r.y(), 1e-8 * (1 + r.norm()));
  }
}

}  // namespace
}  // namespace dba
