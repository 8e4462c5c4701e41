// Observations read in file order, stored point-major (docs/design.md §6,
// Layouts): while the file lists them grouped by point (as BAL files do)
// they are already in place and only counted; once a point index goes down,
// the point of every observation is kept and Finish sorts them (a stable
// counting sort). Both BAL readers (line by line, and in parallel) use it.
//
// Thread safety: one owner.
#pragma once

#include <cstdint>
#include <vector>

#include "dba/problem/problem.h"

namespace dba {

class PointMajorOrder {
 public:
  // The point of the next observation in file order (0 <= point).
  void Add(int64_t point) {
    if (grouped_ && point < last_) Ungroup();
    if (point >= static_cast<int64_t>(counts_.size())) counts_.resize(point + 1, 0);
    if (!grouped_) file_point_.push_back(point);
    ++counts_[point];
    last_ = point;
  }
  // Observations of point k so far.
  int64_t count(int64_t k) const {
    return k < static_cast<int64_t>(counts_.size()) ? counts_[k] : 0;
  }
  // Sets problem->point_offsets for `num_points` points and puts its
  // observations (obs_camera, obs_pixel, in file order) in point-major order.
  void Finish(int64_t num_points, Problem* problem);

 private:
  void Ungroup();

  std::vector<int64_t> counts_;      // observations per point, by point id
  std::vector<int64_t> file_point_;  // point of every observation, once ungrouped
  bool grouped_ = true;
  int64_t last_ = -1;
};

}  // namespace dba
