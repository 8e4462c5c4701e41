// The ground-control file of `dba solve --gcps`: surveyed points and where
// they were measured in the images. Text, two kinds of rows:
//
//   NAME  X  Y  Z  SIGMA_XY  SIGMA_Z  control|check     a surveyed point
//   NAME  IMAGE  x  y                                   a measurement of it
//
// separated by blanks or commas; '#' starts a comment; blank lines are
// skipped; rows of either kind in any order. X, Y, Z are in the priors'
// frame (metres, or --gcp-crs); σ_xy is the σ of each horizontal axis, σ_z
// the vertical one, both > 0. A control point is a 3D point of the solve
// with a prior on its coordinates; a check point never influences the solve
// and is triangulated after it. IMAGE is the image's name (COLMAP models)
// or its 0-based camera index (BAL and .dba problems); x, y are in the input
// format's pixel convention (BAL: origin at the image centre, y up; COLMAP:
// origin at the top-left corner of the top-left pixel, y down).
//
// Thread safety: functions touch only the file they read.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace dba {

struct GroundControlMeasurementRow {
  std::string image;
  Eigen::Vector2d pixel;
  int64_t line = 0;
};

struct GroundControlRow {
  std::string name;
  Eigen::Vector3d xyz;
  Eigen::Vector2d sigma;  // σ_xy, σ_z
  bool control = true;    // else a check point
  int64_t line = 0;
  std::vector<GroundControlMeasurementRow> measurements;  // in file order
};

// Every surveyed point with its measurements, checked: 7 or 4 fields,
// finite numbers, σ > 0, the role, no name twice, every measurement of a
// named point, no image twice for one point, a check point measured in at
// least 2 images, a control point in at least 1. Throws InputError(file,
// line, what was wrong).
std::vector<GroundControlRow> ReadGroundControlFile(const std::string& path);

}  // namespace dba
