// A bundle-adjustment problem with the BAL camera model, held point-major.
//
// This is also the share of one rank in the distributed design (DESIGN.md §2):
// a rank holds its points, their observations and the cameras they touch, with
// cameras renumbered locally. A single process is one rank holding everything.
//
// Memory per observation: one 32-bit camera id and two doubles (20 bytes),
// plus the 64-bit point offsets (8 bytes per point).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace dba {

inline constexpr int kBalCameraSize = 9;  // angle-axis r[3], t[3], f, k1, k2
inline constexpr int kPointSize = 3;

struct BalProblem {
  // Camera parameters, kBalCameraSize per camera.
  std::vector<double> cameras;
  // Point coordinates, kPointSize per point.
  std::vector<double> points;
  // Observations of point k are [point_offsets[k], point_offsets[k+1]).
  // Size num_points() + 1, point_offsets[0] == 0.
  std::vector<int64_t> point_offsets;
  // Camera seeing each observation, and the observed pixel (x, y).
  std::vector<int32_t> obs_camera;
  std::vector<double> obs_pixel;

  int64_t num_cameras() const {
    return static_cast<int64_t>(cameras.size()) / kBalCameraSize;
  }
  int64_t num_points() const {
    return static_cast<int64_t>(points.size()) / kPointSize;
  }
  int64_t num_observations() const {
    return static_cast<int64_t>(obs_camera.size());
  }

  double* camera(int64_t i) { return cameras.data() + kBalCameraSize * i; }
  const double* camera(int64_t i) const {
    return cameras.data() + kBalCameraSize * i;
  }
  double* point(int64_t k) { return points.data() + kPointSize * k; }
  const double* point(int64_t k) const { return points.data() + kPointSize * k; }
  const double* pixel(int64_t obs) const { return obs_pixel.data() + 2 * obs; }

  // Bytes held by the arrays above (capacity, not size).
  int64_t MemoryBytes() const {
    return static_cast<int64_t>(cameras.capacity() * sizeof(double) +
                                points.capacity() * sizeof(double) +
                                point_offsets.capacity() * sizeof(int64_t) +
                                obs_camera.capacity() * sizeof(int32_t) +
                                obs_pixel.capacity() * sizeof(double));
  }
};

}  // namespace dba
