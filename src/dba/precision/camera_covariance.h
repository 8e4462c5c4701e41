// The covariance of every image's pose at the optimum (docs/design.md §8):
// the camera-side block of the inverse normal matrix, which the Schur
// complement gives exactly, Σ_c = S⁻¹ (S = U − W V⁻¹ Wᵀ undamped, at the
// optimum, with the robust weights and the priors' terms), read from S's
// sparse factor by selected inversion (solver/selected_inversion.h): each
// image's 6×6 block, without the dense inverse.
//
// The datum. When camera priors, control points or two held images fix the
// frame, S is positive definite and Σ_c = S⁻¹ (absolute). When nothing does,
// S has the similarity's null space G (7 columns; 1, the scale, beside one
// held image): any covariance then depends on a datum, and the one given is
// the inner constraints over the camera centres (the free network's
// minimum-trace datum: the centres' centroid, their rotation about it and
// their scale undetermined by nothing; Gᵀ W δ = 0 with W selecting the
// centres). It is reached in two steps: d unknowns are pinned (an image's
// pose and one coordinate of the image farthest from it, or that coordinate
// alone), which gives a positive definite S_h and Σ_h = S_h⁻¹ with zero rows
// at the pins; G's columns follow from the same factor,
// g_k = e_k − S_h⁻¹ S e_k (e_k at pin k, zero elsewhere on the pins); then
// the S-transformation P = I − G (Gᵀ W G)⁻¹ Gᵀ W gives
//
//   Σ = P Σ_h Pᵀ = Σ_h − Y K Gᵀ − G Kᵀ Yᵀ + G N Gᵀ,
//   Y = Σ_h W G,  M = Gᵀ W G,  K = M⁻ᵀ,  N = M⁻¹ (Gᵀ W Y) M⁻ᵀ,
//
// for each image's block from Σ_h's block and d + d solves, exact whatever
// pins were taken (P annihilates what they chose).
//
// A pose block is given for (θ, C): θ the camera's attitude error as a small
// rotation about the frame's x, y, z axes (R_cw' = exp([θ]ₓ) R_cw with
// R_cw = R(ω)ᵀ the camera-to-world rotation; from the step's δω by
// θ = −R(ω)ᵀ J_l(ω) δω, camera/pose_step.h), C the centre.
//
// Thread safety: pure functions.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "dba/camera/pose_similarity.h"
#include "dba/problem/problem.h"
#include "dba/rcs/form_rcs.h"

namespace dba {

// What the data leave free of the frame, as the solve's gauge knows it.
struct GaugeFreedom {
  int free = 7;                      // 7 (nothing holds it), 1 (scale), 0
  std::optional<Vec3> scale_centre;  // free == 1: the held image's centre
};

using PoseCovariance = Eigen::Matrix<double, 6, 6>;  // (θ, C)

struct CameraCovariances {
  int datum_free = 0;  // GaugeFreedom::free the covariances were taken under
  // Per image; images held fixed have none.
  std::vector<std::optional<PoseCovariance>> pose;
  int64_t factor_nonzeros = 0;  // scalars in S's factor (selected inversion's)
  double inversion_flops = 0.0;  // solver/selected_inversion.h InversionFlops
  double factor_seconds = 0.0;   // to the factor and the datum's solves
  double seconds = 0.0;          // the whole computation
};

// The pose covariances of `side`'s images (no rigs) from `rcs` at the
// optimum, for unit pixel variance, on `threads` threads (the factor's BLAS
// and the inversion's products). std::runtime_error when S (with the
// datum's pins) is not positive definite: the data do not determine every
// unknown.
CameraCovariances ComputeCameraCovariances(const CameraSide& side, const RcsSystem& rcs,
                                           const GaugeFreedom& freedom, int threads = 1);

// Σ of a pose after the world moved by `s` (X' = s Q X + T):
// θ' = Q θ, C' = s Q C + T, so Σ' = D Σ Dᵀ with D = diag(Q, s Q).
PoseCovariance MovePoseCovariance(const Similarity& s, const PoseCovariance& sigma);

}  // namespace dba
