// A pose's projection centre, and a similarity of the world applied to poses
// and points, in both camera models (the pose's first six parameters are ω,
// angle-axis world -> camera, and t):
//
//   C = -R(ω)ᵀ t
//   X' = s Q X + T  moves a pose (ω, t) to (R(ω) Qᵀ, s t - R(ω) Qᵀ T), so
//   every camera sees the moved points as it saw the old ones (its
//   camera-frame coordinates scale by s, which no projection sees).
//
// Thread safety: pure functions.
#pragma once

#include "dba/camera/rotation.h"

namespace dba {

struct Similarity {
  double scale = 1.0;
  Mat3 rotation = Mat3::Identity();
  Vec3 translation = Vec3::Zero();
  Vec3 Apply(const Vec3& X) const { return scale * (rotation * X) + translation; }
};

// C = -R(ω)ᵀ t of a pose (ω[3], t[3]).
Vec3 CameraCentre(const double* pose);

// P = C + R(ω)ᵀ a: the point at `a` in the pose's own frame (a GNSS
// antenna's lever arm), in the world.
Vec3 AntennaPosition(const double* pose, const Vec3& lever_arm);

// The pose (ω[3], t[3], in place) after the world moved by `s`.
void MovePose(const Similarity& s, double* pose);

}  // namespace dba
