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
#include <string>
#include <vector>

#include "dba/problem/bal_problem.h"

namespace dba {

enum class PartitionScheme { kEqual, kCameraLocality };
const char* PartitionSchemeName(PartitionScheme scheme);
// "equal" or "cameras"; throws std::invalid_argument otherwise.
PartitionScheme ParsePartitionScheme(const std::string& name);

// Group (0..num_groups-1) of every point.
std::vector<int32_t> PartitionPoints(const BalProblem& problem, int num_groups,
                                     PartitionScheme scheme);

// Cameras in breadth-first order over the camera graph (cameras adjacent when
// they share a point), each component started from its lowest-degree camera,
// neighbours visited by increasing degree.
std::vector<int32_t> CameraGraphOrder(const BalProblem& problem);

}  // namespace dba
