// Photogrammetric camera projection and Jacobians; see photo_camera.h.
#include "dba/camera/photo_camera.h"

namespace dba {

Vec2 PhotoResidual(LensModel model, const double* pose, const double* intrinsics,
                   const double* point, const double* observed) {
  return PhotoResidualAndJacobians(model, pose, intrinsics, point, observed, nullptr, nullptr,
                                   nullptr);
}

Vec2 PhotoResidualAndJacobians(LensModel model, const double* pose, const double* intrinsics,
                               const double* point, const double* observed,
                               PoseJacobian* J_pose, IntrinsicsJacobian* J_intrinsics,
                               PointJacobian* J_point) {
  return PhotoResidualAndJacobians(model, MakeRotationFrame(pose), pose, intrinsics, point,
                                   observed, J_pose, J_intrinsics, J_point);
}

Vec2 PhotoResidualAndJacobians(LensModel model, const RotationFrame& frame, const double* pose,
                               const double* intrinsics, const double* point,
                               const double* observed, PoseJacobian* J_pose,
                               IntrinsicsJacobian* J_intrinsics, PointJacobian* J_point) {
  const Vec3 t(pose[3], pose[4], pose[5]);
  const Mat3& R = frame.R;
  const Vec3 P = R * Vec3(point[0], point[1], point[2]) + t;
  const bool geometry = J_pose != nullptr || J_point != nullptr;
  LensPointJacobian du_dP;
  const Vec2 u =
      LensProjectInline(model, intrinsics, P, geometry ? &du_dP : nullptr, J_intrinsics);
  if (!geometry) return u - Vec2(observed[0], observed[1]);
  const PointJacobian du_dX = du_dP * R;
  if (J_pose != nullptr) {
    J_pose->block<2, 3>(0, 0) = -du_dP * SkewSymmetric(P) * frame.J_l;
    J_pose->block<2, 3>(0, 3) = -du_dX;
  }
  if (J_point != nullptr) *J_point = du_dX;
  return u - Vec2(observed[0], observed[1]);
}

}  // namespace dba
