// An image's pose on a rig (docs/design.md §1.7, issue 46; the first brick,
// not yet used by the solve):
//
//   T_image = S ∘ F,   S = sensor_from_rig, F = rig_from_world
//   P_cam = R_s (R_f X + t_f) + t_s,   so R_i = R_s R_f, t_i = R_s t_f + t_s
//
// and the Jacobians of P_cam in the frame's and the sensor's parameters
// (angle-axis ω stepped additively, translations additively; camera/rotation.h):
//
//   ∂P/∂ω_f = −R_s [R_f X]× J_l(ω_f),    ∂P/∂t_f = R_s
//   ∂P/∂ω_s = −[R_s Y]× J_l(ω_s),        ∂P/∂t_s = I,      Y = R_f X + t_f
//
// A residual's Jacobians are ∂r/∂P (its projection's, e.g. J_point R_iᵀ)
// times these. Poses are 6 doubles (ω, t), as everywhere in dba.
//
// Thread safety: pure functions.
#pragma once

#include <Eigen/Core>

#include "dba/camera/rotation.h"

namespace dba {

using CameraPointPoseJacobian = Eigen::Matrix<double, 3, 6>;  // ∂P_cam/∂(ω, t)

// image = sensor ∘ frame.
void ComposeRigPose(const double* sensor_from_rig, const double* rig_from_world, double* image);

// ∂P_cam/∂frame and ∂P_cam/∂sensor at world point X.
struct RigPoseJacobians {
  CameraPointPoseJacobian frame, sensor;
};
RigPoseJacobians RigCameraPointJacobians(const double* sensor_from_rig,
                                         const double* rig_from_world, const Vec3& X);

}  // namespace dba
