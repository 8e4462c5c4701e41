// The pose's LM step; see pose_step.h.
#include "dba/camera/pose_step.h"

#include "dba/camera/pose_similarity.h"

namespace dba {

void PlusPose(const double* pose, const double* delta, double* out) {
  const Vec3 centre = CameraCentre(pose);
  const Vec3 moved_omega = Vec3(pose[0], pose[1], pose[2]) + Vec3(delta[0], delta[1], delta[2]);
  const Vec3 t = -AngleAxisToRotation(moved_omega) * (centre + Vec3(delta[3], delta[4], delta[5]));
  for (int k = 0; k < 3; ++k) out[k] = moved_omega[k], out[3 + k] = t[k];
}

}  // namespace dba
