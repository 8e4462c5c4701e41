// Where a FOV camera's ω starts (docs/camera_models.md, FOV).
//
// COLMAP's FOV model (camera/lens_projection.h) switches to a series when
// ω² < 1e-4, and dba keeps COLMAP's values so that a model means the same in
// both tools. That series bends the lens the opposite way to the closed form
// it replaces (σ ≈ 1 − ω²/12 + ω²|n|²/3, where atan(2|n| tan(ω/2)) / (|n| ω)
// = 1 + ω²/12 − ω²|n|²/3 + O(ω⁴)): inside the series branch any ω ≠ 0 bends
// the lens away from the closed form's barrel distortion, so ω = 0 is a false
// minimum of COLMAP's own model, and LM started there stays (COLMAP's own
// Ceres leaves it only by luck, by a step long enough to jump the boundary).
// A free ω that starts in the series branch therefore starts at COLMAP's
// default 0.01 (its sign kept), the edge of the closed form: the model of
// that start differs from the given one by at most the series' jump
// (5e-5 relative), and LM descends from there along the closed form.
//
// Thread safety: functions of their arguments.
#pragma once

#include <string>
#include <vector>

#include "dba/problem/problem.h"

namespace dba {

// The smallest |ω| on COLMAP's closed-form branch (ω² ≥ 1e-4 in doubles).
inline constexpr double kFovClosedFormOmega = 0.01;

// A FOV group whose free ω was moved out of the series branch.
struct FovStartMove {
  int64_t group;
  double from, to;
};

// Moves each free FOV ω with ω² < 1e-4 to ±0.01 (+ for ω = 0); returns the
// moves, in group order. Fixed ω, and every other model, are left alone.
std::vector<FovStartMove> StartFovOutsideSeries(CameraSide* side);

// "FOV group 0: omega 0.001 starts at 0.01 (...)": one line per move.
std::string DescribeFovStartMoves(const std::vector<FovStartMove>& moves);

}  // namespace dba
