// The photogrammetric camera: a pose per image and an intrinsic group, in
// one of the lens models (problem/lens_model.h), shared by the images taken
// with it. COLMAP's conventions (camera looks down +z, image origin at the
// top-left pixel corner, y down):
//
//   pose  (6 per image):   ω[3] angle-axis, t[3]      (world -> camera)
//   intrinsics:            the group's lens model's parameters, in its order
//
//   P = R(ω) X + t,   u = lens(P) (camera/lens_projection.h),
//   residual r = u - u_observed
//
// Derivatives (∂u/∂P and ∂u/∂intrinsics from the lens), the pose's on its
// step (δω, δC) of camera/pose_step.h:
//   ∂P/∂X = R,  ∂P/∂δC = -R,  ∂P/∂δω = -[P]ₓ J_l(ω)
//
// All functions are pure and thread-safe.
#pragma once

#include "dba/camera/lens_projection.h"
#include "dba/camera/pose_step.h"
#include "dba/camera/rotation.h"

namespace dba {

using PoseJacobian = Eigen::Matrix<double, 2, kPoseSize, Eigen::RowMajor>;
// ∂r/∂intrinsics: the first LensModelParams(model) columns.
using IntrinsicsJacobian = LensParamsJacobian;

Vec2 PhotoResidual(LensModel model, const double* pose, const double* intrinsics,
                   const double* point, const double* observed);

// Residual and Jacobians; any Jacobian pointer may be null.
Vec2 PhotoResidualAndJacobians(LensModel model, const double* pose, const double* intrinsics,
                               const double* point, const double* observed,
                               PoseJacobian* J_pose, IntrinsicsJacobian* J_intrinsics,
                               PointJacobian* J_point);
// The same with the pose's rotation frame given (MakeRotationFrame(pose)).
Vec2 PhotoResidualAndJacobians(LensModel model, const RotationFrame& frame, const double* pose,
                               const double* intrinsics, const double* point,
                               const double* observed, PoseJacobian* J_pose,
                               IntrinsicsJacobian* J_intrinsics, PointJacobian* J_point);

}  // namespace dba
