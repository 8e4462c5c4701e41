// The camera-priors file of `dba solve --camera-priors` (GNSS positions of
// the images): text, one row per image,
//
//   IMAGE  X  Y  Z  [SIGMA_XY  SIGMA_Z]
//
// separated by blanks or commas; '#' starts a comment; blank lines are
// skipped. IMAGE is the image's name (COLMAP models) or its 0-based camera
// index (BAL and .dba problems); X, Y, Z are in a metric Cartesian frame
// (metres); σ_xy is the σ of each horizontal axis (not a radius), σ_z the
// vertical one, both > 0 (without them every row takes --prior-sigma).
//
// Thread safety: functions touch only the file they read.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace dba {

struct CameraPriorRow {
  std::string image;
  Eigen::Vector3d xyz;
  std::optional<Eigen::Vector2d> sigma;  // σ_xy, σ_z
  int64_t line = 0;
};

// Every row, checked: 4 or 6 fields, finite numbers, σ > 0, no image twice.
// Throws InputError(file, line, what was wrong).
std::vector<CameraPriorRow> ReadCameraPriorsFile(const std::string& path);

}  // namespace dba
