// The order in which the two-level preconditioner's aggregation visits S's
// block rows (solver/two_level_preconditioner.h AggregateBlockRows): camera
// rows by the Morton code of their centres (problem/point_order.h
// MortonOrder), then the intrinsic rows in row order.
//
// Why: aggregation is greedy, so which rows end up together depends on the
// order it meets them in. In row order that is the cameras' numbering: the
// same survey numbered by strips or at random had 176 against 155 PCG
// iterations (uavtxt-10000). In the order of the cameras' places
// the aggregates are the same sets whatever the numbering (up to cameras
// that share a Morton cell), and so is PCG's iteration count.
#pragma once

#include <cstdint>
#include <vector>

#include "dba/rcs/unknown_layout.h"

namespace dba {

// Block rows of `layout` in the aggregation's order; x: the camera-side
// parameters.
std::vector<int32_t> AggregationOrder(const UnknownLayout& layout, const double* x);

}  // namespace dba
