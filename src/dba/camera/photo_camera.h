// The photogrammetric camera model with shared intrinsics (the
// paper's 6 exterior + 5 interior unknowns), in COLMAP's conventions (camera
// looks down +z, image origin at the top-left pixel corner, y down):
//
//   pose  (6 per image):           ω[3] angle-axis, t[3]      (world -> camera)
//   intrinsics (5 per camera):     f, cx, cy, k1, k2          (shared by images)
//
//   P = R(ω) X + t,   p = P.xy / P.z,   d = 1 + k1 |p|² + k2 |p|⁴
//   u = f d p + (cx, cy),   residual r = u - u_observed
//
// Derivatives:
//   ∂u/∂p = f (d I + 2 (k1 + 2 k2 |p|²) p pᵀ)
//   ∂p/∂P = [ 1/Pz   0   -Px/Pz² ]
//           [  0   1/Pz  -Py/Pz² ]
//   ∂P/∂X = R,  ∂P/∂t = I,  ∂P/∂ω = -[R X]ₓ J_l(ω)
//   ∂u/∂f = d p,  ∂u/∂(cx, cy) = I,  ∂u/∂k1 = f |p|² p,  ∂u/∂k2 = f |p|⁴ p
// COLMAP's SIMPLE_PINHOLE, PINHOLE (fx = fy), SIMPLE_RADIAL and RADIAL are
// this model with some intrinsics held at zero.
//
// All functions are pure and thread-safe.
#pragma once

#include "dba/camera/rotation.h"

namespace dba {

inline constexpr int kPoseSize = 6;
inline constexpr int kIntrinsicsSize = 5;

using PoseJacobian = Eigen::Matrix<double, 2, kPoseSize, Eigen::RowMajor>;
using IntrinsicsJacobian = Eigen::Matrix<double, 2, kIntrinsicsSize, Eigen::RowMajor>;

Vec2 PhotoResidual(const double* pose, const double* intrinsics, const double* point,
                   const double* observed);

// Residual and Jacobians; any Jacobian pointer may be null.
Vec2 PhotoResidualAndJacobians(const double* pose, const double* intrinsics,
                               const double* point, const double* observed,
                               PoseJacobian* J_pose, IntrinsicsJacobian* J_intrinsics,
                               PointJacobian* J_point);
// The same with the pose's rotation frame given (MakeRotationFrame(pose)).
Vec2 PhotoResidualAndJacobians(const RotationFrame& frame, const double* pose,
                               const double* intrinsics, const double* point,
                               const double* observed, PoseJacobian* J_pose,
                               IntrinsicsJacobian* J_intrinsics, PointJacobian* J_point);

}  // namespace dba
