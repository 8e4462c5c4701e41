// The coarse coordinates of the two-level preconditioner (solver/
// two_level_preconditioner.h): per camera row, the basis in which an
// infinitesimal rigid motion of the whole scene has the same coordinates for
// every camera.
//
// A camera maps a world point X to P = R(ω) (X - C). Moving the scene by
// X' = X + δΩ × (X - c̄) + δT, with c̄ the centroid of the camera centres
// C = -Rᵀt, leaves every observation as it was when each camera moves with
// it: on the pose's step (δω, δC) of camera/pose_step.h,
//
//   δω = -J_l(ω)⁻¹ R δΩ,   δC = δT + δΩ × (C - c̄)
//
// (R(ω + δω) ≈ exp([J_l(ω) δω]ₓ) R(ω), so the camera frame turns by -R δΩ).
// In CoarseRowBasis terms: A = -J_l⁻¹ R, B = I, C = -[C - c̄]ₓ. Scaling the
// scene about c̄, X' = c̄ + (1 + δs)(X - c̄), moves each camera centre the
// same way and leaves its rotation and intrinsics: D = C - c̄. These 7
// similarity motions are S's null space (the gauge freedom); the slow modes
// of PCG on long strips are such motions varying slowly along the strip,
// scale drift among them (Konolige & Brown, arXiv 2007.01941), which an
// aggregate of cameras of different headings only represents in these
// coordinates. c̄ keeps the rotation and scale columns of the size of the
// scene, not of its distance from the origin.
//
// Camera rows of 9 (BAL: δω, δC, f, k1, k2) or 6 unknowns (pose: δω, δC)
// get the rigid basis; intrinsic rows the identity.
#pragma once

#include <vector>

#include "dba/rcs/unknown_layout.h"
#include "dba/solver/coarse_row_basis.h"

namespace dba {

// One basis per block row of `layout`; x: the camera-side parameters.
// `with_scale`: the pose rows also get the scale column D.
std::vector<CoarseRowBasis> RigidMotionBases(const UnknownLayout& layout, const double* x,
                                             bool with_scale);

}  // namespace dba
