// Linearization and Schur elimination of one 3D point (paper eq. 3-5).
//
// For point k with observations a = 1..m by cameras c_a:
//   J_c,a = ∂r_a/∂c (2x9), J_p,a = ∂r_a/∂X_k (2x3), r_a residual
//   V     = Σ_a J_p,aᵀ J_p,a                      (3x3, undamped)
//   g_p   = Σ_a J_p,aᵀ r_a
//   W_a   = J_c,aᵀ J_p,a                           (9x3)
//   V_λ   = V + λ D_p,  D_p = clamp(diag V)        (Marquardt damping)
//   T_a   = W_a V_λ⁻¹
// The point's sub-RCS (eq. 4) is the dense block over its cameras
//   S_ab = δ_ab J_c,aᵀ J_c,a - T_a W_bᵀ
// and its right-hand side contribution b_a = -J_c,aᵀ r_a + T_a g_p.
// Back-substitution (eq. 5): δX = V_λ⁻¹ (-g_p - Σ_a W_aᵀ δc_a).
//
// Thread safety: a PointSystem is scratch for one thread.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dba/camera/bal_camera.h"
#include "dba/problem/bal_problem.h"

namespace dba {

using Mat93 = Eigen::Matrix<double, 9, 3>;
using Mat99 = Eigen::Matrix<double, 9, 9, Eigen::RowMajor>;
using Vec9 = Eigen::Matrix<double, 9, 1>;

// Bounds of the Marquardt scaling D = clamp(diag(JᵀJ)).
struct DampingBounds {
  double min_diagonal = 1e-6;
  double max_diagonal = 1e32;
  double Clamp(double d) const {
    return d < min_diagonal ? min_diagonal
                            : (d > max_diagonal ? max_diagonal : d);
  }
};

struct PointSystem {
  int num_obs = 0;
  std::vector<CameraJacobian> J_c;
  std::vector<PointJacobian> J_p;
  std::vector<Vec2> r;
  std::vector<Mat93> W;
  std::vector<Mat93> T;  // W_a V_λ⁻¹
  Eigen::Matrix3d V;
  Eigen::Matrix3d V_inv;  // V_λ⁻¹
  Vec3 g_p;
  double cost = 0.0;  // ½ Σ |r_a|²
};

// Residuals, Jacobians, V, g_p, W and the cost of point k at the problem's
// current parameters.
void LinearizePoint(const BalProblem& problem, int64_t k, PointSystem* sys);

// Damps V with λ, inverts it and forms T_a = W_a V_λ⁻¹.
void EliminatePoint(double lambda, const DampingBounds& bounds,
                    PointSystem* sys);

}  // namespace dba
