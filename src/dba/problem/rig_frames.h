// The frames of a rig problem (docs/design.md §1.7) as the readers check
// them: a frame is one exposure of its rig, so it holds one image per
// sensor (intrinsic group) at most.
// Thread safety: pure functions.
#pragma once

#include <cstdint>

#include "dba/problem/problem.h"

namespace dba {

// Two images of one sensor in one frame: the frame, the group, and the
// images (first < second).
struct SensorTwice {
  int64_t frame = -1;  // -1: none
  int64_t group = -1;
  int64_t first = -1, second = -1;
};

// The first (by the second image's index) frame of `side` holding two
// images of one sensor; frame -1 when none, or without rigs. `side`'s
// image_frame must be in range.
SensorTwice FindSensorTwice(const CameraSide& side);

}  // namespace dba
