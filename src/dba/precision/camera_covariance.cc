// Pose and intrinsics covariances from the camera side's inverse; see
// camera_covariance.h (docs/design.md §8).
#include "dba/precision/camera_covariance.h"

#include <numeric>
#include <stdexcept>

#include "dba/camera/pose_step.h"
#include "dba/camera/rotation.h"
#include "dba/common/timer.h"

namespace dba {
namespace {

// (δω, δC) -> (θ, C) of the pose at `pose`.
Eigen::Matrix<double, 6, 6> AttitudeCoordinates(const double* pose) {
  const Vec3 omega(pose[0], pose[1], pose[2]);
  Eigen::Matrix<double, 6, 6> T = Eigen::Matrix<double, 6, 6>::Identity();
  T.topLeftCorner<3, 3>() = -AngleAxisToRotation(omega).transpose() * SO3LeftJacobian(omega);
  return T;
}

std::vector<int64_t> RowUnknowns(const UnknownLayout& layout, int32_t r, int count) {
  std::vector<int64_t> rows(count);
  std::iota(rows.begin(), rows.end(), layout.row_offset(r));
  return rows;
}

}  // namespace

CameraCovariances CameraBlocks(const CameraSide& side, const UnknownLayout& layout,
                               const CameraSideInverse& inverse) {
  CameraCovariances out;
  out.datum_free = inverse.free();
  out.pose.resize(side.num_images());
  for (int64_t image = 0; image < side.num_images(); ++image) {
    const int32_t r = layout.camera_row(image);
    if (r < 0) continue;
    if (inverse.undetermined(r)) {
      out.undetermined_images.push_back(image);
      continue;
    }
    const PoseCovariance sigma = inverse.Block(RowUnknowns(layout, r, kPoseSize));
    const Eigen::Matrix<double, 6, 6> T = AttitudeCoordinates(side.camera(image));
    out.pose[image] = T * sigma * T.transpose();
  }
  if (side.model != CameraModel::kPhoto) return out;
  for (int64_t g = 0; g < side.num_groups(); ++g) {
    const int32_t r = layout.intrinsics_row(g);
    if (r < 0) continue;
    if (inverse.undetermined(r)) {
      out.undetermined_groups.push_back(g);
      continue;
    }
    IntrinsicsCovariance c;
    c.group = g;
    const int n = layout.intrinsic_unknowns(r);
    for (int j = 0; j < n; ++j) {
      c.parameters.push_back(LensModelParamName(side.group_model(g), layout.intrinsics_free_index(g)[j]));
    }
    c.covariance = inverse.Block(RowUnknowns(layout, r, n));
    out.intrinsics.push_back(std::move(c));
  }
  return out;
}

CameraCovariances ComputeCameraCovariances(const CameraSide& side, const RcsSystem& rcs,
                                           const GaugeFreedom& freedom, int threads) {
  if (side.has_rigs()) throw std::runtime_error("--covariance: rig models are not supported yet");
  const Timer timer;
  const CameraSideInverse inverse(side, rcs, freedom, threads);
  CameraCovariances out = CameraBlocks(side, rcs.layout, inverse);
  out.factor_nonzeros = inverse.factor_values();
  out.inversion_flops = inverse.inversion_flops();
  out.factor_seconds = inverse.factor_seconds();
  out.seconds = timer.Seconds();
  return out;
}

PoseCovariance MovePoseCovariance(const Similarity& s, const PoseCovariance& sigma) {
  Eigen::Matrix<double, 6, 6> D = Eigen::Matrix<double, 6, 6>::Zero();
  D.topLeftCorner<3, 3>() = s.rotation;
  D.bottomRightCorner<3, 3>() = s.scale * s.rotation;
  return D * sigma * D.transpose();
}

}  // namespace dba
