// Linearization and Schur elimination of one 3D point (paper eq. 3-5).
//
// For point k with observations a = 1..m, each observation touches up to two
// camera-side blocks of unknowns (rcs/unknown_layout.h): its camera c_a (the
// 9 BAL parameters, or a 6-parameter pose) and, in the photogrammetric model,
// its intrinsic group g_a (the group's free parameters, ≤ kMaxIntrinsics). Either may be
// held fixed, and then has no block. With e ranging over an observation's
// blocks:
//   J_e,a = ∂r_a/∂(block e) (2 x |e|), J_p,a = ∂r_a/∂X_k (2x3), r_a residual
//   V     = Σ_a J_p,aᵀ J_p,a                      (3x3, undamped)
//   g_p   = Σ_a J_p,aᵀ r_a
//   W_e,a = J_e,aᵀ J_p,a                           (|e| x 3)
//   V_λ   = V + λ D_p,  D_p = clamp(diag V)        (Marquardt damping)
//   T_e,a = W_e,a V_λ⁻¹
// The point's sub-RCS (eq. 4) is the dense block over its blocks
//   S_ef += [a == b] J_e,aᵀ J_f,b - T_e,a W_f,bᵀ
// and its right-hand side contribution b_e += -J_e,aᵀ r_a + T_e,a g_p.
// With K_a = J_p,a V_λ⁻¹ (2x3), T_e,a W_f,bᵀ = J_e,aᵀ K_a J_p,bᵀ J_f,b, so
//   S_ef += J_e,aᵀ M_ab J_f,b,   M_ab = [a == b] I₂ - K_a J_p,bᵀ   (2x2)
//   b_e  += -J_e,aᵀ (r_a - K_a g_p)
// a rank-2 update per pair of observations (eq. 4 as the kernels compute it,
// rcs/form_rcs.cc): no W or T per observation, and the own Gram term of a
// diagonal block in the same pass.
// Back-substitution (eq. 5): δX = V_λ⁻¹ (-g_p - Σ_a Σ_e W_e,aᵀ δ_e), computed
// as V_λ⁻¹ (-Σ_a J_p,aᵀ (r_a + Σ_e J_e,a δ_e)), which needs no W.
//
// A control point (problem.h, PointPrior) adds one more residual on X alone,
// r₀ = w ∘ (X - X₀) with J₀ = diag(w): V += diag(w²), g_p += w ∘ r₀, and the
// cost ½|r₀|². It touches no camera, so S and b change only through V.
//
// The intrinsics Jacobian keeps only the free parameters, packed into its
// first columns (the rest zero), so fixed ones are not unknowns.
//
// With rigs (camera/rig_pose.h) J_c is the observation's Jacobian in its
// frame's step, and a refined sensor pose's six columns follow the free
// intrinsics in J_i: the sensor is one more shared block of its group's
// row, and two images of one frame seeing the point are two observations
// on one camera row (the kernels handle both already).
//
// Thread safety: a PointSystem is scratch for one thread.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dba/camera/bal_camera.h"
#include "dba/camera/photo_camera.h"
#include "dba/camera/rotation_frame_cache.h"
#include "dba/problem/problem.h"
#include "dba/rcs/robust_loss.h"
#include "dba/rcs/unknown_layout.h"

namespace dba {

// Bounds of the Marquardt scaling D = clamp(diag(JᵀJ)).
struct DampingBounds {
  double min_diagonal = 1e-6;
  double max_diagonal = 1e32;
  double Clamp(double d) const {
    return d < min_diagonal ? min_diagonal
                            : (d > max_diagonal ? max_diagonal : d);
  }
};

// Plain (uncorrected) squared residuals: over all observations and over the
// inliers of a robust loss (|r| ≤ its scale; all, for the squared loss).
struct ResidualSums {
  double squared = 0.0;          // Σ |r|²
  double inlier_squared = 0.0;   // Σ |r|² over inliers
  double inliers = 0.0;          // count (a double: summed with the others)
  void Add(double s, bool inlier) {
    squared += s;
    if (inlier) inlier_squared += s, inliers += 1.0;
  }
  void Add(const ResidualSums& o) {
    squared += o.squared, inlier_squared += o.inlier_squared, inliers += o.inliers;
  }
};

// The camera models as the kernels see them: unknowns of the camera block
// and of the intrinsics block (0: the model has none).
struct BalModel {
  static constexpr int kCamera = kBalCameraSize;
  static constexpr int kIntrinsics = 0;
};
// The photogrammetric model with intrinsics blocks of at most kWidth
// unknowns: the kernels are instantiated for 5 (the paper's model and every
// model with ≤ 5 parameters), 8, 12 and 16, so a problem pays only for the
// width its largest block needs.
template <int kWidth>
struct PhotoModelOf {
  static constexpr int kCamera = kPhotoPoseSize;
  static constexpr int kIntrinsics = kWidth;
};
using PhotoModel = PhotoModelOf<kPhotoIntrinsicsSize>;

// f.template operator()<M>() with M the narrowest PhotoModelOf whose width
// holds `max_block` unknowns (UnknownLayout::max_intrinsics_block).
template <class F>
decltype(auto) WithPhotoModel(int max_block, F&& f) {
  if (max_block <= 5) return f.template operator()<PhotoModelOf<5>>();
  if (max_block <= 8) return f.template operator()<PhotoModelOf<8>>();
  if (max_block <= 12) return f.template operator()<PhotoModelOf<12>>();
  return f.template operator()<PhotoModelOf<16>>();
}

template <class Model>
struct PointSystem {
  static constexpr int kC = Model::kCamera;
  // (a placeholder width when the model has no intrinsics block)
  static constexpr int kI = Model::kIntrinsics > 0 ? Model::kIntrinsics : 2;
  using CameraJac = Eigen::Matrix<double, 2, kC, Eigen::RowMajor>;
  using IntrinsicsJac = Eigen::Matrix<double, 2, kI, Eigen::RowMajor>;
  using IntrinsicsW = Eigen::Matrix<double, kI, 3>;

  int num_obs = 0;
  std::vector<int32_t> camera_row;      // -1: camera held fixed
  std::vector<int32_t> intrinsics_row;  // -1: none, or all held fixed
  std::vector<CameraJac> J_c;
  std::vector<IntrinsicsJac> J_i;       // free columns first, rest zero
  std::vector<PointJacobian> J_p;
  std::vector<Vec2> r;
  std::vector<PointJacobian> K;         // K_a = J_p,a V_λ⁻¹
  std::vector<IntrinsicsW> W_i;         // W_i,a (T_i is formed per group, form_rcs.cc)
  Eigen::Matrix3d V;
  Eigen::Matrix3d V_inv;  // V_λ⁻¹
  // Rotation frames of the current cameras (a PointSystem lives for one
  // formation or back-substitution).
  RotationFrameCache frames;
  // With rigs: the frames' (by frame) and the sensors' (by num_frames +
  // group) rotation frames.
  RotationFrameCache rig_frames;
  Vec3 g_p;
  double cost = 0.0;  // ½ Σ ρ(|r_a|²) (r, J above are the corrected ones)
  // ½ Σ (ρ(|r_a|²) - |r̃_a|²): the model ½ |r̃ + J̃ δ|² plus this is the
  // robust model (0 for the squared loss).
  double model_offset = 0.0;
  ResidualSums residuals;  // of the uncorrected residuals (observations only)
  // A control point's prior (null: none) and its residual r₀ = w ∘ (X - X₀)
  // (its cost is in `cost`).
  const PointPrior* prior = nullptr;
  Vec3 prior_r;
};

// Residuals, Jacobians, V, g_p and the cost of point k at the problem's
// current parameters, each observation's residual and Jacobians corrected
// for `loss` (rcs/robust_loss.h); `problem.model` must match Model.
template <class Model>
void LinearizePoint(const Problem& problem, const UnknownLayout& layout,
                    const RobustLoss& loss, int64_t k, PointSystem<Model>* sys);

// V_λ⁻¹ = (V + λ clamp(diag V))⁻¹ only (all back-substitution needs).
// Undamped (the analyse stage at the optimum), a V that its observations
// leave singular (one observation, parallel rays) has the generalized
// inverse V⁺ instead: the point absorbs what it can of its observations,
// and its null direction, which nothing determines, gives the cameras
// nothing (docs/design.md §8).
template <class Model>
void InvertDampedV(double lambda, const DampingBounds& bounds, PointSystem<Model>* sys);

// Whether V determines its point: every eigenvalue above 1e-12 of the
// largest (a triangulation angle of 1e-6 rad still is).
bool PointDetermined(const Eigen::Matrix3d& V);
// V⁺ over the eigenvalues PointDetermined counts.
Eigen::Matrix3d GeneralizedInverse(const Eigen::Matrix3d& V);

// InvertDampedV, then K_a = J_p,a V_λ⁻¹ and W_i,a = J_i,aᵀ J_p,a.
template <class Model>
void EliminatePoint(double lambda, const DampingBounds& bounds, PointSystem<Model>* sys);

}  // namespace dba
