// Ground-truth errors; see ground_truth.h.
#include "dba/synthetic/ground_truth.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "dba/camera/bal_camera.h"

namespace dba {
namespace {

Eigen::Matrix3Xd Centres(const std::vector<double>& cameras) {
  const int64_t n = static_cast<int64_t>(cameras.size()) / kBalCameraSize;
  Eigen::Matrix3Xd c(3, n);
  for (int64_t i = 0; i < n; ++i) {
    const double* p = cameras.data() + kBalCameraSize * i;
    const Mat3 R = AngleAxisToRotation(Vec3(p[0], p[1], p[2]));
    c.col(i) = -R.transpose() * Vec3(p[3], p[4], p[5]);  // C = -Rᵀ t
  }
  return c;
}

}  // namespace

GroundTruthErrors CompareWithGroundTruth(const BalProblem& truth,
                                         const std::vector<double>& cameras,
                                         const std::vector<double>& points) {
  if (cameras.size() != truth.cameras.size() || points.size() != truth.points.size()) {
    throw std::invalid_argument(
        "the ground truth does not match the problem (different numbers of cameras or points)");
  }
  GroundTruthErrors e;
  double sum = 0.0;
  for (int64_t k = 0; k < truth.num_points(); ++k) {
    for (int64_t o = truth.point_offsets[k]; o < truth.point_offsets[k + 1]; ++o) {
      sum += BalResidual(cameras.data() + kBalCameraSize * truth.obs_camera[o],
                         points.data() + kPointSize * k, truth.pixel(o))
                 .squaredNorm();
    }
  }
  // Per observation, like the solver's RMS: sqrt(Σ |r|² / observations).
  e.rms_to_noise_free_px = std::sqrt(sum / std::max<int64_t>(truth.num_observations(), 1));

  const Eigen::Matrix3Xd solved = Centres(cameras), true_centres = Centres(truth.cameras);
  const Eigen::Matrix4d T = Eigen::umeyama(solved, true_centres, /*with_scaling=*/true);
  const Eigen::Matrix3d sR = T.topLeftCorner<3, 3>();
  const Vec3 shift = T.topRightCorner<3, 1>();
  e.similarity_scale = std::cbrt(sR.determinant());
  e.camera_centre_rms = std::sqrt(
      ((sR * solved).colwise() + shift - true_centres).colwise().squaredNorm().mean());
  double point_sum = 0.0;
  for (int64_t k = 0; k < truth.num_points(); ++k) {
    const Vec3 X = sR * Eigen::Map<const Vec3>(points.data() + 3 * k) + shift;
    point_sum += (X - Eigen::Map<const Vec3>(truth.point(k))).squaredNorm();
  }
  e.point_rms = std::sqrt(point_sum / std::max<int64_t>(truth.num_points(), 1));
  return e;
}

}  // namespace dba
