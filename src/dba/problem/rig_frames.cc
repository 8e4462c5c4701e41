// The frames' structure; see rig_frames.h.
#include "dba/problem/rig_frames.h"

#include <unordered_map>

namespace dba {

SensorTwice FindSensorTwice(const CameraSide& side) {
  std::unordered_map<int64_t, int64_t> image_of;  // frame * groups + group -> image
  const int64_t groups = side.num_groups();
  for (int64_t i = 0; side.has_rigs() && i < side.num_images(); ++i) {
    const int64_t f = side.image_frame[i], g = side.camera_intrinsics[i];
    const auto [other, fresh] = image_of.emplace(f * groups + g, i);
    if (!fresh) return {f, g, other->second, i};
  }
  return {};
}

}  // namespace dba
