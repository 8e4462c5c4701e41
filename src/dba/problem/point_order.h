// The points of a problem in an order that keeps neighbours together, and
// a problem's points permuted (with their observations and priors) into a
// given order and back.
//
// Why: RCS formation and back-substitution walk the points in storage order,
// each thread a contiguous range. Points next to each other in space are
// seen by the same few cameras, so in a spatial order consecutive points
// write the same S blocks (cache hits) and each thread's range touches its
// own cameras (few rows shared between threads). In an input's own order
// (incremental SfM's, Bundler's, a merged block's, or shuffled) they write
// all over S: formation 2.8x and back-substitution 3.2x slower per pass on
// a 2,500-image survey. The order is the Z-order (Morton) curve
// of the points' positions: O(P log P), no graph; the same positions give
// the same order whatever the input's numbering.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "dba/problem/problem.h"

namespace dba {

// new position -> item: the n = xyz.size() / 3 positions sorted by their
// Morton code, quantized as SpatialPointOrder says; ties in their order.
std::vector<int64_t> MortonOrder(std::span<const double> xyz);

// new position -> point in `problem`: the points sorted by the Morton code
// of their positions quantized to 2^21 cells per axis over the cube that
// holds the 1st to 99th percentile on every axis (points beyond it, e.g.
// near infinity, clamped to its faces); ties in their input order.
std::vector<int64_t> SpatialPointOrder(const Problem& problem);

// The fraction of consecutive points of `order` (empty: the problem's own
// order) seen by at least one common camera: how often the next point
// writes where the last one did. Over at most about a million pairs, evenly
// spread (a million-image survey has 83 million points).
double SharedCameraFraction(const Problem& problem, std::span<const int64_t> order = {});

// The walk the solves should take: SpatialPointOrder, or empty (the
// problem's own order) where that already shares cameras between
// consecutive points at least 0.8 times as often as the spatial order (a
// generated survey's footprints, incremental SfM's growth): then it costs
// no table and no copy. (Distance is no guide: a generator that lists a
// footprint's points at random across it is local in cameras, and faster
// than the Morton walk at a million images.) A walked solve numbers the
// cameras as the walk first sees them (CamerasInPointOrder over the walked
// points): the cameras of neighbouring points are then neighbours in
// memory, in S's rows and in the rotation cache. An input whose order is
// local keeps its numbering (numbering it by the walk too cost an ordered
// survey's formation 8-10%); the preconditioner's aggregates take a
// canonical order of their own (rcs/aggregation_order.h).
std::vector<int64_t> PointWalk(const Problem& problem);

// new position -> camera: the cameras in the order the points, walked in
// `order` (empty: as stored), first observe them (the new cameras of one
// point by the pixel it is seen at, not by the input's order of its
// observations), then the cameras no point observes.
std::vector<int64_t> CamerasInPointOrder(const Problem& problem, std::span<const int64_t> order = {});

// Moves camera (image) `order[k]` to position k: its parameters (a BAL
// camera or a pose; intrinsic groups stay), its group, its fixed flag, and
// every observation's camera index. `order` is a permutation of the images.
// A walked solve runs on cameras in CamerasInPointOrder: the cameras of neighbouring
// points are then neighbours in memory and in the rotation cache, not
// scattered over the input's numbering.
void PermuteCameras(std::span<const int64_t> order, Problem* problem);

// Moves point `order[k]` (with its observations, in their order, and its
// prior) to position k. `order` is a permutation of the points. Transient
// memory: one array at a time (at most 16 bytes per observation).
void PermutePoints(std::span<const int64_t> order, Problem* problem);

// The inverse permutation: inverse[order[k]] = k.
std::vector<int64_t> InversePermutation(std::span<const int64_t> order);

}  // namespace dba
