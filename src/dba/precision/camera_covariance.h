// The covariance of every image's pose and every intrinsic group at the
// optimum (docs/design.md §8), read from the camera side's inverse under the
// solve's datum (precision/camera_side_inverse.h): each image's 6×6 and each
// group's block over its free parameters, for unit pixel variance.
//
// A pose block is given for (θ, C): θ the camera's attitude error as a small
// rotation about the frame's x, y, z axes (R_cw' = exp([θ]ₓ) R_cw with
// R_cw = R(ω)ᵀ the camera-to-world rotation; from the step's δω by
// θ = −R(ω)ᵀ J_l(ω) δω, camera/pose_step.h), C the centre.
//
// Thread safety: pure functions.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dba/precision/camera_side_inverse.h"

namespace dba {

using PoseCovariance = Eigen::Matrix<double, 6, 6>;  // (θ, C)

// An intrinsic group's free parameters (named by its lens model) and their
// covariance.
struct IntrinsicsCovariance {
  int64_t group = 0;
  std::vector<std::string> parameters;
  Eigen::MatrixXd covariance;
};

struct CameraCovariances {
  int datum_free = 0;  // GaugeFreedom::free the covariances were taken under
  // Per image; images held fixed and those the data do not determine
  // (listed below) have none.
  std::vector<std::optional<PoseCovariance>> pose;
  std::vector<IntrinsicsCovariance> intrinsics;  // determined groups with free parameters
  std::vector<int64_t> undetermined_images, undetermined_groups;  // ascending
  int64_t factor_nonzeros = 0;  // scalars in S's factor (selected inversion's)
  double inversion_flops = 0.0;  // solver/selected_inversion.h InversionFlops
  double factor_seconds = 0.0;   // to the factor and the datum's solves
  double seconds = 0.0;          // the whole computation
};

// The pose and intrinsics blocks of `side` (no rigs) from its inverse.
CameraCovariances CameraBlocks(const CameraSide& side, const UnknownLayout& layout,
                               const CameraSideInverse& inverse);

// CameraSideInverse and CameraBlocks in one, timed.
CameraCovariances ComputeCameraCovariances(const CameraSide& side, const RcsSystem& rcs,
                                           const GaugeFreedom& freedom, int threads = 1);

// Σ of a pose after the world moved by `s` (X' = s Q X + T):
// θ' = Q θ, C' = s Q C + T, so Σ' = D Σ Dᵀ with D = diag(Q, s Q).
PoseCovariance MovePoseCovariance(const Similarity& s, const PoseCovariance& sigma);

}  // namespace dba
