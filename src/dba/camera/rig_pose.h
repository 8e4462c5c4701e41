// An image's pose on a rig and the Jacobians of its residual in the rig's
// unknowns (docs/design.md §1.7):
//
//   T_image = S ∘ F,   S = sensor_from_rig, F = rig_from_world
//   R_i = R_s R_f,   t_i = R_s t_f + t_s,   C_i = C_f + R_fᵀ c_s
//
// with C = -Rᵀ t a pose's centre (c_s: the sensor's place in the rig). The
// frame and the sensor step as every pose in dba (camera/pose_step.h): the
// rotation ω additively about the pose's own centre, then the centre, so a
// left perturbation φ = J_l(ω) δω turns R ← exp([φ]×) R. To first order
//
//   frame (δω_f, δC_f):   φ_i = R_s J_l(ω_f) δω_f,   δC_i = δC_f + R_fᵀ [c_s]× J_l(ω_f) δω_f
//   sensor (δω_s, δc_s):  φ_i = J_l(ω_s) δω_s,       δC_i = R_fᵀ δc_s
//
// and a residual r with ∂r/∂X = J_X (so ∂r/∂P = J_X R_iᵀ, P = R_i X + t_i
// the point in the image's frame) has ∂r/∂φ_i = -(∂r/∂P) [P]× and
// ∂r/∂C_i = -J_X, hence
//
//   J_frame  = [ J_φ R_s J_l(ω_f) - J_X R_fᵀ [c_s]× J_l(ω_f),   -J_X ]
//   J_sensor = [ J_φ J_l(ω_s),                                   -J_X R_fᵀ ]
//
// For the rig's origin (S = I) J_frame is the image's own pose Jacobian.
//
// Thread safety: pure functions.
#pragma once

#include <Eigen/Core>

#include "dba/camera/photo_camera.h"
#include "dba/camera/pose_similarity.h"
#include "dba/camera/rotation.h"
#include "dba/problem/problem.h"

namespace dba {

// image = sensor ∘ frame.
void ComposeRigPose(const double* sensor_from_rig, const double* rig_from_world, double* image);

// out = a ∘ b⁻¹ (the pose taking b's frame to a's): with a an image's pose
// and b its frame's, the sensor's pose in the rig.
void ComposeWithInverse(const double* a, const double* b, double* out);

// Every image's pose composed from its frame and its group's sensor
// (side->has_rigs(); nothing otherwise).
void ComposeRigImages(CameraSide* side);

// Where image i's exposure's pose is in side.cameras: the image's own, with
// rigs its frame's (rig_from_world).
inline int64_t ExposurePoseOffset(const CameraSide& side, int64_t i) {
  return side.has_rigs() ? side.frame_offset(side.image_frame[i]) : int64_t{side.camera_size()} * i;
}

// The world moved by `s` (camera/pose_similarity.h) in a problem with rigs:
// every frame but the `held` ones (one flag per frame; empty: none) moves
// as a pose, every sensor's place in its rig scales with the world (its
// turn is relative, unchanged); the images are left to ComposeRigImages.
void MoveRigFrames(const Similarity& s, const std::vector<uint8_t>& held, CameraSide* side);

// The per-(frame, sensor) 3x3 factors of the chain above, at the current
// poses: frame_phi = R_s J_l(ω_f), frame_centre = R_fᵀ [c_s]× J_l(ω_f),
// sensor_phi = J_l(ω_s), sensor_centre = R_fᵀ.
struct RigChain {
  Mat3 frame_phi, frame_centre, sensor_phi, sensor_centre;
};
RigChain MakeRigChain(const RotationFrame& frame, const RotationFrame& sensor,
                      const double* sensor_from_rig);

// J_frame and J_sensor (either may be null) of an observation whose image
// has rotation R_i and sees the point at P = R_i X + t_i, with ∂r/∂X = J_X.
void RigResidualJacobians(const RigChain& chain, const Mat3& R_image, const Vec3& P,
                          const PointJacobian& J_X, PoseJacobian* J_frame,
                          PoseJacobian* J_sensor);

}  // namespace dba
