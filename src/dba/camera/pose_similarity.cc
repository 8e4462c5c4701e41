// Projection centres and similarities of poses; see pose_similarity.h.
#include "dba/camera/pose_similarity.h"

#include <Eigen/Geometry>

namespace dba {

Vec3 CameraCentre(const double* pose) {
  const Mat3 R = AngleAxisToRotation(Vec3(pose[0], pose[1], pose[2]));
  return -R.transpose() * Vec3(pose[3], pose[4], pose[5]);
}

Vec3 AntennaPosition(const double* pose, const Vec3& lever_arm) {
  if (lever_arm.isZero(0.0)) return CameraCentre(pose);
  const Mat3 R = AngleAxisToRotation(Vec3(pose[0], pose[1], pose[2]));
  return CameraCentre(pose) + R.transpose() * lever_arm;
}

void MovePose(const Similarity& s, double* pose) {
  const Mat3 R = AngleAxisToRotation(Vec3(pose[0], pose[1], pose[2])) * s.rotation.transpose();
  const Eigen::AngleAxisd aa(R);
  const Vec3 omega = aa.angle() * aa.axis();
  const Vec3 t = s.scale * Vec3(pose[3], pose[4], pose[5]) - R * s.translation;
  for (int k = 0; k < 3; ++k) pose[k] = omega[k], pose[3 + k] = t[k];
}

}  // namespace dba
