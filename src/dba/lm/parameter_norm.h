// ‖x‖ of LM's step-size stop, ‖δ‖ ≤ ε (‖x‖ + ε) (levenberg_marquardt.h),
// measured so that where the world's origin is changes nothing:
//
//   ‖x‖² = Σ_free cameras (|ω|² + |C - C̄|² + its other free parameters²)
//        + Σ_free intrinsic parameters²  +  Σ_points |X - X̄|²
//
// with C = -R(ω)ᵀ t a camera's centre, C̄ the free cameras' centroid and X̄
// the points' (rcs/position_spread.h). The step δ = (δω, δC, ...) moves a
// camera's centre (camera/pose_step.h), so both sides of the test are
// measured alike. With raw t and X, in ECEF coordinates (|X| ≈ 6.4e6 m)
// ‖x‖ is about √n · 6.4e6 for n points and cameras: with a million, any
// step under about 64 in norm counted as converged.
// Thread safety: pure function.
#pragma once

#include <vector>

#include "dba/rcs/position_spread.h"
#include "dba/rcs/unknown_layout.h"

namespace dba {

// `cameras` laid out as the problem's camera side, `points` the spread of
// the points' positions.
double ParameterNorm(const UnknownLayout& layout, const std::vector<double>& cameras,
                     const PositionSpread& points);

}  // namespace dba
