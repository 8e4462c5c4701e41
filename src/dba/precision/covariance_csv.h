// --covariance FILE: one line per image, a header first (comma-separated,
// nothing else, for any CSV reader). Columns:
//
//   image      the image's name (COLMAP) or 0-based index in the input
//   datum      inner (the inner constraints over the camera centres) or
//              absolute (priors, control points or held images fix the
//              frame); held: the image was held fixed (no covariance);
//              undetermined: the data do not determine it (too few
//              observations; no figures, the others' computed without it)
//   sigma_x, sigma_y, sigma_z       the centre's standard deviations
//   c_xx, c_xy, c_xz, c_yy, c_yz, c_zz   the centre's covariance
//   sigma_omega_deg, sigma_phi_deg, sigma_kappa_deg
//              the attitude's standard deviations, in degrees, as small
//              rotations of the camera about the frame's x, y, z axes
//   p11 ... p66  the pose's 6×6 covariance (upper triangle, row by row) in
//              (θx, θy, θz radians, x, y, z), the same rotations and centre
//   x, y, z    the centre itself
//
// in the output's frame (the solve's; the local east-north-up frame of the
// report when georeferenced), after the gauge's similarity, scaled by
// `scale` (σ̂₀², or 1).
//
// Thread safety: pure functions (the write: one file).
#pragma once

#include <string>
#include <vector>

#include "dba/precision/camera_covariance.h"

namespace dba {

// The figures the files hold, as matrices: a pose's or a point's block
// after the gauge's similarity, scaled.
PoseCovariance PoseInOutputFrame(const PoseCovariance& pose, const Similarity& moved, double scale);
Eigen::Matrix3d PointInOutputFrame(const Eigen::Matrix3d& point, const Similarity& moved, double scale);

// --point-covariance FILE: "point,sigma_x,sigma_y,sigma_z,c_xx,c_xy,c_xz,
// c_yy,c_yz,c_zz", a line per point: points[k] named loaded[k] (its index in
// the input), k < loaded.size(), after the gauge's similarity (s² Q Σ Qᵀ),
// scaled by `scale`. A point its observations do not determine (NaN in
// `points`) has its line's fields empty.
std::string PointCovarianceCsv(const std::vector<Eigen::Matrix3d>& points,
                               const std::vector<int64_t>& loaded, const Similarity& moved, double scale);

// An image's `datum` column: inner or absolute (the datum), held or
// undetermined (no figures).
std::string PoseState(const CameraCovariances& covariances, size_t image);

// FILE's text; `centres`: each image's centre in the output's frame (the
// last columns x, y, z, also for held and undetermined images).
std::string CovarianceCsv(const CameraCovariances& covariances, const std::vector<std::string>& names,
                          const std::vector<Vec3>& centres, const Similarity& moved, double scale);

}  // namespace dba
