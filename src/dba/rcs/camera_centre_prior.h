// A prior on a camera's position (a GNSS antenna's), in either camera model:
// the pose's first six parameters are ω (angle-axis, world -> camera; with
// rigs, world -> rig: the frame's pose) and t, so its centre is
// C = -R(ω)ᵀ t, and the antenna, at `a` in the pose's own frame (its lever
// arm: the camera's, with rigs the rig's), is at
//
//   P = C + R(ω)ᵀ a,        r = Σ⁻¹ (P - P_prior),   Σ = diag(σ_x, σ_y, σ_z)
//
// (σ_x = σ_y = σ_xy; a = 0, the default, puts the antenna at the centre).
// Its Jacobian on the pose's step (δω, δC) (camera/pose_step.h: ω' = ω + δω,
// R(ω + δω) ≈ exp([J_l(ω) δω]ₓ) R(ω)) and on the lever arm, when that is an
// unknown (stepped additively):
//
//   ∂P/∂δω = R(ω)ᵀ [a]ₓ J_l(ω),   ∂P/∂δC = I,   ∂P/∂a = R(ω)ᵀ.
//
// A prior on image i is on its exposure's pose (camera/rig_pose.h
// ExposurePoseOffset). A prior touches its pose's row and the lever arm's: the point-by-point
// Schur elimination is unchanged.
//
// Thread safety: pure functions.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dba/camera/pose_similarity.h"
#include "dba/camera/rig_pose.h"
#include "dba/rcs/robust_loss.h"

namespace dba {

struct CameraCentrePrior {
  int32_t image = 0;  // 0-based image (camera) index in the problem
  Vec3 centre = Vec3::Zero();  // P_prior
  Vec3 sigma = Vec3::Ones();  // σ_x, σ_y, σ_z (> 0)
};

// A solve's camera priors, their robust loss and the antenna's lever arm.
struct CameraPriors {
  std::vector<CameraCentrePrior> priors;
  RobustLoss loss;  // on |r|², r in units of σ
  Vec3 lever_arm = Vec3::Zero();  // a (metres, in the camera's or rig's frame)
  bool refine_lever_arm = false;  // a is then 3 unknowns of the solve
  bool empty() const { return priors.empty(); }
};

using CentrePriorJacobian = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;  // ∂r/∂(δω, δC)
using LeverArmJacobian = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;     // ∂r/∂a

// r (above), and ∂r/∂(δω, δC) and ∂r/∂a when J and J_a are not null.
Vec3 CentrePriorResidual(const double* pose, const Vec3& lever_arm, const CameraCentrePrior& prior,
                         CentrePriorJacobian* J, LeverArmJacobian* J_a = nullptr);

}  // namespace dba
