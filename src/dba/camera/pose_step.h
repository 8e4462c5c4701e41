// How an LM step moves a pose (ω, t), in both camera models (docs/design.md
// §6): the camera turns about its own centre C = -R(ω)ᵀ t and the centre
// moves in the world,
//
//   δ = (δω, δC):   ω' = ω + δω,   C' = C + δC,   t' = -R(ω') C'.
//
// With P = R(ω) X + t = R(ω) (X - C) the point in the camera's frame,
//
//   ∂P/∂δω = -[P]ₓ J_l(ω),   ∂P/∂δC = -R(ω) = -∂P/∂X,
//
// so a camera's centre columns of the Jacobian are minus its point columns.
//
// Why not t' = t + δt: then ∂P/∂ω = -[R X]ₓ J_l, and turning a camera about
// its own centre moves t on a circle of radius |C| about the world origin. A
// block's slow mode (its doming: cameras tilt and rise together over the
// whole block) is such a motion, bent in (ω, t) and nearly straight in
// (ω, C): with additive t, Gauss-Newton crept along it at a cost decrease
// ratio of 0.93 per LM iteration on a 2,000-image survey (the origin 1.6 km
// from the cameras), and took 20 LM iterations on a 100,000-image survey
// against 8 with this step (bench/README.md).
//
// Thread safety: pure functions.
#pragma once

namespace dba {

// A pose's parameters (ω, t) and its step's unknowns (δω, δC).
inline constexpr int kPoseSize = 6;

// out[0..5] = pose[0..5] ⊞ delta[0..5] (out may alias pose).
void PlusPose(const double* pose, const double* delta, double* out);

}  // namespace dba
