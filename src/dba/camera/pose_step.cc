// The pose's LM step; see pose_step.h.
#include "dba/camera/pose_step.h"

#include "dba/camera/rotation.h"

namespace dba {

void PlusPose(const double* pose, const double* delta, double* out) {
  const Vec3 omega(pose[0], pose[1], pose[2]);
  const Vec3 centre = -AngleAxisToRotation(omega).transpose() * Vec3(pose[3], pose[4], pose[5]);
  const Vec3 moved_omega = omega + Vec3(delta[0], delta[1], delta[2]);
  const Vec3 t = -AngleAxisToRotation(moved_omega) * (centre + Vec3(delta[3], delta[4], delta[5]));
  for (int k = 0; k < 3; ++k) out[k] = moved_omega[k], out[3 + k] = t[k];
}

}  // namespace dba
