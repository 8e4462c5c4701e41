// An image's pose on a rig and its Jacobians; see rig_pose.h (the equations).
#include "dba/camera/rig_pose.h"

#include <Eigen/Geometry>

namespace dba {

void ComposeRigPose(const double* sensor_from_rig, const double* rig_from_world, double* image) {
  const Mat3 R_s = AngleAxisToRotation(Vec3(sensor_from_rig[0], sensor_from_rig[1], sensor_from_rig[2]));
  const Mat3 R_f = AngleAxisToRotation(Vec3(rig_from_world[0], rig_from_world[1], rig_from_world[2]));
  const Eigen::AngleAxisd aa(R_s * R_f);
  const Vec3 omega = aa.angle() * aa.axis();
  const Vec3 t = R_s * Vec3(rig_from_world[3], rig_from_world[4], rig_from_world[5]) +
                 Vec3(sensor_from_rig[3], sensor_from_rig[4], sensor_from_rig[5]);
  for (int k = 0; k < 3; ++k) image[k] = omega[k], image[3 + k] = t[k];
}

RigPoseJacobians RigCameraPointJacobians(const double* sensor_from_rig,
                                         const double* rig_from_world, const Vec3& X) {
  const RotationFrame s = MakeRotationFrame(sensor_from_rig);
  const RotationFrame f = MakeRotationFrame(rig_from_world);
  const Vec3 RfX = f.R * X;
  const Vec3 Y = RfX + Vec3(rig_from_world[3], rig_from_world[4], rig_from_world[5]);
  RigPoseJacobians J;
  J.frame.leftCols<3>() = -s.R * SkewSymmetric(RfX) * f.J_l;
  J.frame.rightCols<3>() = s.R;
  J.sensor.leftCols<3>() = -SkewSymmetric(s.R * Y) * s.J_l;
  J.sensor.rightCols<3>() = Mat3::Identity();
  return J;
}

}  // namespace dba
