// Division of the 3D points into groups, one per rank (paper section 6.1).
//
//   kEqual           the paper's split: consecutive points, equal counts
//   kCameraLocality  points grouped by the cameras that see them: cameras are
//                    ordered along the camera graph (breadth-first, as in
//                    Cuthill-McKee), cut into groups of about equal
//                    observation counts, and each point goes to the group of
//                    its first camera in that order. A rank then touches few
//                    cameras beyond its own, so its sub-RCS stays small.
//
// Thread safety: pure functions.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "dba/problem/problem.h"

namespace dba {

enum class PartitionScheme { kEqual, kCameraLocality };
const char* PartitionSchemeName(PartitionScheme scheme);
// "equal" or "cameras"; throws std::invalid_argument otherwise.
PartitionScheme ParsePartitionScheme(const std::string& name);

// Group (0..num_groups-1) of every point.
std::vector<int32_t> PartitionPoints(const Problem& problem, int num_groups,
                                     PartitionScheme scheme);

// The visibility graph as a stream of chunks of whole points: calls
// visit(first_point, offsets (n + 1 global observation indices), cameras of
// observations offsets[0] .. offsets[n]) for consecutive chunks.
using VisibilityChunkFn = std::function<void(int64_t, std::span<const int64_t>,
                                             std::span<const int32_t>)>;
using VisibilityStream = std::function<void(const VisibilityChunkFn&)>;

// The same partition from a visibility stream (read twice for kCameraLocality,
// not at all for kEqual), so the graph never has to be in memory at once.
std::vector<int32_t> PartitionPoints(int64_t num_cameras, int64_t num_points,
                                     int64_t num_observations, int num_groups,
                                     PartitionScheme scheme,
                                     const VisibilityStream& stream);

// Cameras in breadth-first order over the camera graph (cameras adjacent when
// they share a point), each component started from its lowest-degree camera,
// neighbours visited by increasing degree.
std::vector<int32_t> CameraGraphOrder(const Problem& problem);
std::vector<int32_t> CameraGraphOrder(int64_t num_cameras, const VisibilityStream& stream);

}  // namespace dba
