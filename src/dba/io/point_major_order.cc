// Observations to point-major order; see point_major_order.h.
#include "dba/io/point_major_order.h"

#include <algorithm>

namespace dba {

// Not grouped after all: the (sorted) point ids so far, from the counts.
void PointMajorOrder::Ungroup() {
  grouped_ = false;
  int64_t seen = 0;
  for (int64_t c : counts_) seen += c;
  file_point_.reserve(static_cast<size_t>(seen));
  for (int64_t p = 0; p < static_cast<int64_t>(counts_.size()); ++p) {
    file_point_.insert(file_point_.end(), counts_[p], p);
  }
}

void PointMajorOrder::Finish(int64_t num_points, Problem* problem) {
  std::vector<int64_t>& offsets = problem->point_offsets;
  counts_.resize(num_points, 0);
  offsets.assign(num_points + 1, 0);
  for (int64_t k = 0; k < num_points; ++k) offsets[k + 1] = offsets[k] + counts_[k];
  std::vector<int64_t>().swap(counts_);
  if (grouped_) return;
  // Stable counting sort by point: offsets[k] .. offsets[k+1] is point k.
  const int64_t n = static_cast<int64_t>(file_point_.size());
  std::vector<int64_t> next(offsets.begin(), offsets.end() - 1);
  std::vector<int32_t> camera(n);
  std::vector<double> pixel(2 * n);
  for (int64_t j = 0; j < n; ++j) {
    const int64_t d = next[file_point_[j]]++;
    camera[d] = problem->obs_camera[j];
    pixel[2 * d] = problem->obs_pixel[2 * j];
    pixel[2 * d + 1] = problem->obs_pixel[2 * j + 1];
  }
  std::vector<int64_t>().swap(file_point_);
  problem->obs_camera.swap(camera);
  problem->obs_pixel.swap(pixel);
}

}  // namespace dba
