// Point back-substitution (paper eq. 5) fused with the evaluation of the step:
// for each point, at the current parameters,
//   δX_k = V_λ⁻¹ (-g_p - Σ_a Σ_e W_e,aᵀ δ_e)   (e: the observation's blocks)
//   model residual  r_a + Σ_e J_e,a δ_e + J_p,a δX_k   (the linearized cost)
//   candidate residual r_a(c_a + δc_a, X_k + δX_k)  (the true cost at the step)
// and a control point's prior residual w ∘ (X - X₀) likewise.
// With a robust loss, r and J are the corrected ones (rcs/robust_loss.h) and
// the costs are ½ Σ ρ.
// Jacobians are recomputed, not stored (docs/design.md §7.1).
//
// Thread safety: runs its own threads; the outputs are written per point.
#pragma once

#include <vector>

#include "dba/problem/problem.h"
#include "dba/rcs/eliminate_point.h"
#include "dba/rcs/position_spread.h"
#include "dba/rcs/unknown_layout.h"

namespace dba {

struct StepEvaluation {
  double model_cost = 0.0;      // ½ Σ |r̃ + J̃ δ|² + model offsets (robust model)
  double candidate_cost = 0.0;  // ½ Σ ρ(|r(x + δ)|²)
  ResidualSums candidate_residuals;      // plain |r(x + δ)|²
  double point_step_squared_norm = 0.0;  // Σ |δX|²
  PositionSpread point_spread;           // the points X (not X + δX) about their centroid
};

// `delta_c` holds one value per unknown of `layout` (the problem's own);
// `candidate_cameras` = cameras ⊞ δc, laid out as problem.cameras.
// X + δX is written to `candidate_points`.
StepEvaluation BackSubstitute(const Problem& problem, const UnknownLayout& layout,
                              double lambda,
                              const DampingBounds& bounds,
                              const std::vector<double>& delta_c,
                              const std::vector<double>& candidate_cameras,
                              int num_threads,
                              std::vector<double>* candidate_points,
                              const RobustLoss& loss = RobustLoss());

}  // namespace dba
