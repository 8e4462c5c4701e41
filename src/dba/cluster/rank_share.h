// One rank's share of a problem (DESIGN.md §2): its points, their
// observations and the cameras they touch, renumbered locally in increasing
// global order (so a local block (i <= j) maps to a global block (i' <= j')).
//
// Thread safety: pure function.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "dba/problem/bal_problem.h"

namespace dba {

struct RankShare {
  BalProblem problem;                 // local camera ids
  std::vector<int32_t> global_camera;  // local camera -> global camera
  std::vector<int64_t> global_point;   // local point -> global point
};

// The points with point_group[k] == group, in global order.
RankShare ExtractShare(const BalProblem& full, std::span<const int32_t> point_group,
                       int32_t group);

}  // namespace dba
