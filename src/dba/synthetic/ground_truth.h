// How close a solution is to the known ground truth of a synthetic problem
// :
//   - reprojection RMS of the solved cameras and points against the
//     noise-free observations (pixels, per observation: sqrt(Σ|r|² / n), as
//     the solver's RMS), which for an exact solver is well below the
//     injected noise's σ√2;
//   - camera-centre and point errors after the similarity transform
//     (rotation, translation, scale; Umeyama) that best maps the solved
//     camera centres onto the true ones, since bundle adjustment fixes the
//     solution only up to such a transform; or, `absolute`, with no
//     transform (a georeferenced solve, whose frame is the truth's). The centre is C = -Rᵀ t in both
//     camera models (the photogrammetric pose's R has COLMAP's axes, which
//     does not change C);
//   - photogrammetric model: per intrinsic group the absolute errors
//     |f - f_true|, |cx - cx_true|, |cy - cy_true|, |k1 - k1_true|,
//     |k2 - k2_true| (intrinsics do not change under a similarity, so they
//     are compared as they are);
//   - rigs: each sensor's pose in its rig (rotation, and place scaled by the
//     alignment's scale).
//
// Thread safety: pure function.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "dba/problem/problem.h"

namespace dba {

struct GroundTruthErrors {
  // Over the true inliers of the points that count: the observations whose
  // loaded pixel is a generated mismatch (IsTrueOutlier) are left out, as
  // their noise-free pixel is not what was matched.
  double rms_to_noise_free_px = 0.0;
  int64_t rms_observations = 0;
  int64_t mismatches_left_out = 0;
  double camera_centre_rms = 0.0;  // in the truth's units, after alignment
  double point_rms = 0.0;
  double similarity_scale = 1.0;
  bool absolute = false;  // no similarity applied
  // Per camera (image): the true centre's x and y and the aligned centre's
  // distance from it (for a top view of the errors over the survey).
  std::vector<double> centre_x, centre_y, centre_error;
  // kPhoto: per intrinsic group, its lens model and |solved - true| of each
  // of its parameters (in the model's order); the true first parameter (the
  // focal length, f or fx) of each group, for relative errors. Empty for
  // kBal.
  std::vector<LensModel> intrinsics_model;
  std::vector<std::vector<double>> intrinsics_error;
  std::vector<double> true_focal;
  // Rigs: per group whose sensor is not its rig's origin, the angle between
  // the solved and the true sensor_from_rig rotations (degrees; a
  // similarity does not change it) and the distance between the sensor's
  // place in its rig, scaled by the alignment's scale, and the true one.
  std::vector<int64_t> sensor_group;
  std::vector<double> sensor_rotation_error_deg, sensor_position_error;
};

// `truth` is the ground-truth problem (true parameters, noise-free pixels);
// `cameras` (the whole camera-side vector) and `points` the solved
// parameters in the same numbering, of a problem with camera model `model`.
// Throws std::invalid_argument when the sizes or the model differ from the
// truth's. `point_kept` (optional, one flag per point): only these points
// and their observations count (points dropped by outlier rejection are no
// longer part of the solution). `loaded_pixels` (optional, 2 per truth
// observation): the pixels the problem was loaded with, to leave the
// generated mismatches out of the RMS.
GroundTruthErrors CompareWithGroundTruth(const Problem& truth,
                                         const std::vector<double>& cameras,
                                         const std::vector<double>& points,
                                         CameraModel model = CameraModel::kBal,
                                         std::span<const uint8_t> point_kept = {},
                                         std::span<const double> loaded_pixels = {},
                                         bool absolute = false);

// The same from a ground-truth file; a binary one is streamed (only its
// camera side and points are held), so large problems do not need twice the
// memory.
GroundTruthErrors CompareWithGroundTruthFile(const std::string& truth_path,
                                             const std::vector<double>& cameras,
                                             const std::vector<double>& points,
                                             CameraModel model = CameraModel::kBal,
                                             std::span<const uint8_t> point_kept = {},
                                             std::span<const double> loaded_pixels = {},
                                             bool absolute = false);

}  // namespace dba
