// R(ω) and J_l(ω) of recently seen cameras, direct-mapped by camera index:
// neighbouring points share cameras, so most observations find their
// camera's frame here and the trigonometry runs about once per camera and
// pass instead of once per observation. No memory per camera.
//
// Valid for one set of camera parameters (a formation, a back-substitution's
// current or candidate cameras): Clear() before the parameters change.
// Thread safety: scratch for one thread.
#pragma once

#include <array>
#include <cstdint>

#include "dba/camera/rotation.h"

namespace dba {

class RotationFrameCache {
 public:
  RotationFrameCache() { Clear(); }
  void Clear() { camera_.fill(-1); }
  // The frame of `camera`, whose angle-axis rotation is omega[0..2].
  const RotationFrame& Get(int32_t camera, const double* omega) {
    const int slot = camera & (kSlots - 1);
    if (camera_[slot] != camera) {
      frame_[slot] = MakeRotationFrame(omega);
      camera_[slot] = camera;
    }
    return frame_[slot];
  }
  // Whether `camera`'s frame is still held (a later Get may have taken its
  // slot).
  bool Holds(int32_t camera) const { return camera_[camera & (kSlots - 1)] == camera; }

 private:
  static constexpr int kSlots = 256;
  std::array<int32_t, kSlots> camera_;
  std::array<RotationFrame, kSlots> frame_;
};

}  // namespace dba
