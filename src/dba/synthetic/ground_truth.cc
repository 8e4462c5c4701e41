// Ground-truth errors; see ground_truth.h.
#include "dba/synthetic/ground_truth.h"

#include "dba/camera/pose_similarity.h"

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>

#include "dba/camera/bal_camera.h"
#include "dba/camera/observation_residual.h"
#include "dba/io/binary_problem.h"
#include "dba/io/read_problem.h"
#include "dba/synthetic/uav_generator.h"

namespace dba {
namespace {

// Camera centres C = -Rᵀ t of the cameras (poses) in `cameras`, laid out
// like side.cameras.
Eigen::Matrix3Xd Centres(const Problem& side, const std::vector<double>& cameras) {
  const int64_t n = side.num_images();
  Eigen::Matrix3Xd c(3, n);
  for (int64_t i = 0; i < n; ++i) {
    c.col(i) = CameraCentre(cameras.data() + side.camera_size() * i);
  }
  return c;
}

// Σ |r|² of the solved parameters against noise-free observations of
// points [first, first + n); `side` is the truth's camera side (model, image
// groups).
struct SquaredSum {
  double sum = 0.0;
  int64_t count = 0;
  int64_t left_out = 0;  // generated mismatches
};
SquaredSum SquaredResiduals(const Problem& side, int64_t first, std::span<const int64_t> offsets,
                            std::span<const int32_t> obs_camera, std::span<const double> pixels,
                            const std::vector<double>& cameras, const std::vector<double>& points,
                            std::span<const uint8_t> point_kept,
                            std::span<const double> loaded_pixels) {
  SquaredSum s;
  for (size_t k = 0; k + 1 < offsets.size(); ++k) {
    if (!point_kept.empty() && !point_kept[first + static_cast<int64_t>(k)]) continue;
    const double* X = points.data() + kPointSize * (first + static_cast<int64_t>(k));
    for (int64_t o = offsets[k]; o < offsets[k + 1]; ++o) {
      const int64_t j = o - offsets[0];
      if (!loaded_pixels.empty() && IsTrueOutlier(&loaded_pixels[2 * o], &pixels[2 * j])) {
        ++s.left_out;
        continue;
      }
      s.sum += ObservationResidual(side, cameras.data(), obs_camera[j], X, pixels.data() + 2 * j)
                   .squaredNorm();
      ++s.count;
    }
  }
  return s;
}

// Per observation, like the solver's RMS: sqrt(Σ |r|² / observations).
void SetRms(const SquaredSum& s, GroundTruthErrors* e) {
  e->rms_to_noise_free_px = std::sqrt(s.sum / std::max<int64_t>(s.count, 1));
  e->rms_observations = s.count;
  e->mismatches_left_out = s.left_out;
}

void CheckLoadedPixels(int64_t truth_observations, std::span<const double> loaded_pixels) {
  if (!loaded_pixels.empty() && static_cast<int64_t>(loaded_pixels.size()) != 2 * truth_observations) {
    throw std::invalid_argument(
        "the ground truth does not match the problem (different numbers of observations)");
  }
}

void CheckSizes(const Problem& truth, const std::vector<double>& cameras,
                const std::vector<double>& points, CameraModel model) {
  if (truth.model != model) {
    throw std::invalid_argument(
        std::string("the ground truth's camera model (") +
        (truth.model == CameraModel::kPhoto ? "photogrammetric" : "BAL") +
        ") differs from the problem's");
  }
  if (cameras.size() != truth.cameras.size() || points.size() != truth.points.size()) {
    throw std::invalid_argument(
        "the ground truth does not match the problem (different numbers of cameras, intrinsic "
        "groups or points)");
  }
}

// Rigs: each non-origin sensor's rotation and (scaled) place against the
// truth's.
void SensorErrors(const Problem& truth, const std::vector<double>& cameras, GroundTruthErrors* e) {
  for (int64_t g = 0; g < truth.num_groups(); ++g) {
    if (truth.sensor_kind[g] == kRigOrigin) continue;
    const double* solved = cameras.data() + truth.sensor_offset(g);
    const double* real = truth.cameras.data() + truth.sensor_offset(g);
    const Mat3 R = AngleAxisToRotation(Eigen::Map<const Vec3>(solved));
    const Mat3 R_true = AngleAxisToRotation(Eigen::Map<const Vec3>(real));
    e->sensor_group.push_back(g);
    e->sensor_rotation_error_deg.push_back(Eigen::AngleAxisd(R * R_true.transpose()).angle() * 180.0 /
                                           M_PI);
    e->sensor_position_error.push_back(
        (e->similarity_scale * CameraCentre(solved) - CameraCentre(real)).norm());
  }
}

// Alignment and intrinsics errors; `truth` needs its camera side and points
// only.
GroundTruthErrors GeometryErrors(const Problem& truth, const std::vector<double>& cameras,
                                 const std::vector<double>& points,
                                 std::span<const uint8_t> point_kept, bool absolute) {
  GroundTruthErrors e;
  e.absolute = absolute;
  const Eigen::Matrix3Xd solved = Centres(truth, cameras), true_centres = Centres(truth, truth.cameras);
  const Eigen::Matrix4d T = absolute ? Eigen::Matrix4d::Identity()
                                     : Eigen::Matrix4d(Eigen::umeyama(solved, true_centres,
                                                                      /*with_scaling=*/true));
  const Eigen::Matrix3d sR = T.topLeftCorner<3, 3>();
  const Vec3 shift = T.topRightCorner<3, 1>();
  e.similarity_scale = std::cbrt(sR.determinant());
  const Eigen::RowVectorXd squared =
      ((sR * solved).colwise() + shift - true_centres).colwise().squaredNorm();
  e.camera_centre_rms = std::sqrt(squared.mean());
  e.centre_x.resize(true_centres.cols());
  e.centre_y.resize(true_centres.cols());
  e.centre_error.resize(true_centres.cols());
  for (Eigen::Index i = 0; i < true_centres.cols(); ++i) {
    e.centre_x[i] = true_centres(0, i);
    e.centre_y[i] = true_centres(1, i);
    e.centre_error[i] = std::sqrt(squared[i]);
  }
  double point_sum = 0.0;
  int64_t point_count = 0;
  for (int64_t k = 0; k < truth.num_points(); ++k) {
    if (!point_kept.empty() && !point_kept[k]) continue;
    ++point_count;
    const Vec3 X = sR * Eigen::Map<const Vec3>(points.data() + 3 * k) + shift;
    point_sum += (X - Eigen::Map<const Vec3>(truth.point(k))).squaredNorm();
  }
  e.point_rms = std::sqrt(point_sum / std::max<int64_t>(point_count, 1));
  for (int64_t g = 0; g < truth.num_groups(); ++g) {
    const LensModel m = truth.group_model(g);
    std::vector<double> err(LensModelParams(m));
    for (size_t j = 0; j < err.size(); ++j) {
      const int64_t at = truth.intrinsics_offset(g) + static_cast<int64_t>(j);
      err[j] = std::abs(cameras[at] - truth.cameras[at]);
    }
    e.intrinsics_model.push_back(m);
    e.intrinsics_error.push_back(std::move(err));
    e.true_focal.push_back(truth.intrinsics(g)[0]);
  }
  if (truth.has_rigs()) SensorErrors(truth, cameras, &e);
  return e;
}

}  // namespace

GroundTruthErrors CompareWithGroundTruth(const Problem& truth,
                                         const std::vector<double>& cameras,
                                         const std::vector<double>& points, CameraModel model,
                                         std::span<const uint8_t> point_kept,
                                         std::span<const double> loaded_pixels, bool absolute) {
  CheckSizes(truth, cameras, points, model);
  CheckLoadedPixels(truth.num_observations(), loaded_pixels);
  GroundTruthErrors e = GeometryErrors(truth, cameras, points, point_kept, absolute);
  const SquaredSum s = SquaredResiduals(truth, 0, truth.point_offsets, truth.obs_camera,
                                        truth.obs_pixel, cameras, points, point_kept,
                                        loaded_pixels);
  SetRms(s, &e);
  return e;
}

GroundTruthErrors CompareWithGroundTruthFile(const std::string& path,
                                             const std::vector<double>& cameras,
                                             const std::vector<double>& points,
                                             CameraModel model,
                                             std::span<const uint8_t> point_kept,
                                             std::span<const double> loaded_pixels,
                                             bool absolute) {
  if (!IsBinaryProblem(path)) {
    return CompareWithGroundTruth(ReadProblem(path), cameras, points, model, point_kept,
                                  loaded_pixels, absolute);
  }
  const BinaryProblemHeader h = ReadBinaryProblemHeader(path);
  CheckLoadedPixels(h.num_observations, loaded_pixels);
  Problem truth(ReadBinaryCameraSide(path));  // camera side and points only
  // Point coordinates of the truth, read in one go (3 doubles per point).
  truth.points = ReadBinaryPointCoordinates(path);
  CheckSizes(truth, cameras, points, model);
  SquaredSum sum;
  ForEachObservationChunk(path, 1 << 20, true,
                          [&](int64_t first, std::span<const int64_t> offsets,
                              std::span<const int32_t> c, std::span<const double> px) {
                            const SquaredSum s = SquaredResiduals(truth, first, offsets, c, px,
                                                                  cameras, points, point_kept,
                                                                  loaded_pixels);
                            sum.sum += s.sum;
                            sum.count += s.count;
                            sum.left_out += s.left_out;
                          });
  GroundTruthErrors e = GeometryErrors(truth, cameras, points, point_kept, absolute);
  SetRms(sum, &e);
  return e;
}

}  // namespace dba
