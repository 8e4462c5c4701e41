// A prior on a camera's centre (a GNSS position), in either camera model:
// the pose's first six parameters are ω (angle-axis, world -> camera) and t,
// so the centre is C = -R(ω)ᵀ t, and the residual, per axis in units of its
// σ, is
//
//   r = Σ⁻¹ (C - C_prior),   Σ = diag(σ_x, σ_y, σ_z)   (σ_x = σ_y = σ_xy)
//
// with the Jacobian on the pose's step (δω, δC) (camera/pose_step.h):
//   ∂C/∂δω = 0,   ∂C/∂δC = I,
// so the prior is exactly quadratic in the step. A prior touches only its
// camera's pose: the point-by-point Schur elimination is unchanged.
//
// Thread safety: pure functions.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dba/camera/pose_similarity.h"
#include "dba/rcs/robust_loss.h"

namespace dba {

struct CameraCentrePrior {
  int32_t image = 0;  // 0-based image (camera) index in the problem
  Vec3 centre = Vec3::Zero();
  Vec3 sigma = Vec3::Ones();  // σ_x, σ_y, σ_z (> 0)
};

// A solve's camera-centre priors and their robust loss.
struct CameraPriors {
  std::vector<CameraCentrePrior> priors;
  RobustLoss loss;  // on |r|², r in units of σ
  bool empty() const { return priors.empty(); }
};

using CentrePriorJacobian = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;  // ∂r/∂(δω, δC)

// r (above), and ∂r/∂(δω, δC) when J is not null.
Vec3 CentrePriorResidual(const double* pose, const CameraCentrePrior& prior,
                         CentrePriorJacobian* J);

}  // namespace dba
