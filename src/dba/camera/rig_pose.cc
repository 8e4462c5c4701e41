// An image's pose on a rig and its Jacobians; see rig_pose.h (the equations).
#include "dba/camera/rig_pose.h"

#include <Eigen/Geometry>

#include "dba/camera/pose_similarity.h"

namespace dba {

void ComposeRigPose(const double* sensor_from_rig, const double* rig_from_world, double* image) {
  const Mat3 R_s = AngleAxisToRotation(Vec3(sensor_from_rig[0], sensor_from_rig[1], sensor_from_rig[2]));
  const Mat3 R_f = AngleAxisToRotation(Vec3(rig_from_world[0], rig_from_world[1], rig_from_world[2]));
  const Vec3 t = R_s * Vec3(rig_from_world[3], rig_from_world[4], rig_from_world[5]) +
                 Vec3(sensor_from_rig[3], sensor_from_rig[4], sensor_from_rig[5]);
  // The rig's origin: the frame's own angle-axis, not one re-extracted from R.
  const bool origin = sensor_from_rig[0] == 0.0 && sensor_from_rig[1] == 0.0 &&
                      sensor_from_rig[2] == 0.0;
  const Eigen::AngleAxisd aa(R_s * R_f);
  const Vec3 omega = origin ? Vec3(rig_from_world[0], rig_from_world[1], rig_from_world[2])
                            : Vec3(aa.angle() * aa.axis());
  for (int k = 0; k < 3; ++k) image[k] = omega[k], image[3 + k] = t[k];
}

void ComposeWithInverse(const double* a, const double* b, double* out) {
  const Vec3 t = -(AngleAxisToRotation(Vec3(b[0], b[1], b[2])).transpose() * Vec3(b[3], b[4], b[5]));
  const double inverse[6] = {-b[0], -b[1], -b[2], t[0], t[1], t[2]};
  ComposeRigPose(a, inverse, out);
}

void ComposeRigImages(CameraSide* side) {
  if (!side->has_rigs()) return;
  for (int64_t i = 0; i < side->num_images(); ++i) {
    const int64_t g = side->camera_intrinsics[i];
    ComposeRigPose(side->cameras.data() + side->sensor_offset(g),
                   side->cameras.data() + side->frame_offset(side->image_frame[i]),
                   side->camera(i));
  }
}

void MoveRigFrames(const Similarity& s, const std::vector<uint8_t>& held, CameraSide* side) {
  for (int64_t f = 0; f < side->num_frames(); ++f) {
    if (held.empty() || !held[f]) MovePose(s, side->cameras.data() + side->frame_offset(f));
  }
  for (int64_t g = 0; g < side->num_groups(); ++g) {
    double* t = side->cameras.data() + side->sensor_offset(g) + 3;
    for (int k = 0; k < 3; ++k) t[k] *= s.scale;
  }
}

RigChain MakeRigChain(const RotationFrame& frame, const RotationFrame& sensor,
                      const double* sensor_from_rig) {
  const Vec3 c_s = CameraCentre(sensor_from_rig);
  RigChain chain;
  chain.frame_phi = sensor.R * frame.J_l;
  chain.sensor_centre = frame.R.transpose();
  chain.frame_centre = chain.sensor_centre * SkewSymmetric(c_s) * frame.J_l;
  chain.sensor_phi = sensor.J_l;
  return chain;
}

void RigResidualJacobians(const RigChain& chain, const Mat3& R_image, const Vec3& P,
                          const PointJacobian& J_X, PoseJacobian* J_frame,
                          PoseJacobian* J_sensor) {
  const Eigen::Matrix<double, 2, 3> J_P = J_X * R_image.transpose();
  const Eigen::Matrix<double, 2, 3> J_phi = -J_P * SkewSymmetric(P);
  if (J_frame != nullptr) {
    J_frame->leftCols<3>() = J_phi * chain.frame_phi - J_X * chain.frame_centre;
    J_frame->rightCols<3>() = -J_X;
  }
  if (J_sensor != nullptr) {
    J_sensor->leftCols<3>() = J_phi * chain.sensor_phi;
    J_sensor->rightCols<3>() = -J_X * chain.sensor_centre;
  }
}

}  // namespace dba
