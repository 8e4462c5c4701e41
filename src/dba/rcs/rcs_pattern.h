// Symbolic phase of the RCS (paper section 5): which blocks of
// S = U - W V⁻¹ Wᵀ are non-zero. Block (i, j) exists iff rows i and j are
// touched by a common point, or i == j. A point touches the rows of the
// cameras that see it and (photogrammetric model) of their intrinsic groups.
//
// Thread safety: pure function.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "dba/problem/problem.h"
#include "dba/rcs/unknown_layout.h"

namespace dba {

// Sorted, unique packed (row <= col) blocks (see PackBlock) of the RCS over
// `num_cameras` cameras, from the point-major visibility lists. Memory stays
// O(number of RCS blocks + a chunk), not O(pairs of observations).
std::vector<uint64_t> RcsBlockPattern(int64_t num_cameras,
                                      std::span<const int64_t> point_offsets,
                                      std::span<const int32_t> obs_camera);

// The RCS pattern over the unknowns of `layout` (rows of fixed cameras and
// groups absent; the lever arm's row, when it has one, meets every camera
// row). Built row by row from a transpose of the visibility (4
// bytes per point and row it touches, held while it runs) instead of
// sorting every pair: the problem's observations are in memory anyway.
std::vector<uint64_t> RcsBlockPattern(const Problem& problem, const UnknownLayout& layout);

}  // namespace dba
