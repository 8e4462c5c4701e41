// Point clouds as PLY files (binary_little_endian 1.0), for viewing adjusted
// structure in MeshLab, CloudCompare and the like:
//
//   ply
//   format binary_little_endian 1.0
//   comment written by dba
//   element vertex N
//   property double x
//   property double y
//   property double z
//   property uchar red
//   property uchar green
//   property uchar blue
//   end_header
//   N records of 27 bytes: x, y, z (IEEE doubles, little-endian), r, g, b
//
// Without colours, each point is coloured by its height z as in the paper's
// figures: blue (low) through cyan, green and yellow to red (high), over the
// range between the 1st and 99th percentiles of the finite z values (linear
// interpolation between order statistics; points outside are clamped to blue
// or red; a non-finite z is blue; when the range is empty every point is
// green).
//
// Thread safety: safe for distinct paths.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace dba {

// The height colour of t in [0, 1] (clamped; NaN counts as 0): 0 blue
// (0, 0, 255), 1/4 cyan (0, 255, 255), 1/2 green (0, 255, 0), 3/4 yellow
// (255, 255, 0), 1 red (255, 0, 0), linear in between, rounded to nearest.
std::array<uint8_t, 3> HeightColour(double t);

// The colours of `values` on that ramp over the range between their 1st and
// 99th percentiles (as the heights above; non-finite: blue), 3 per value.
std::vector<uint8_t> RampColours(std::span<const double> values);

// Writes the points (x, y, z per point) with their colours (r, g, b per
// point), or height colours when `rgb` is empty. Atomic: the file is written
// under a temporary name and renamed over `path` only when complete, so a
// failed write leaves no file (and an existing file untouched).
// std::invalid_argument when xyz.size() is not a multiple of 3 or rgb is
// neither empty nor xyz.size() long; std::runtime_error naming `path` when
// the file cannot be written.
void WritePointCloudPly(const std::string& path, std::span<const double> xyz,
                        std::span<const uint8_t> rgb);

}  // namespace dba
