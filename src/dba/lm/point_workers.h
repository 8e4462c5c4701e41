// The points' side of a solve, as the LM loop on the main rank sees it
// (docs/design.md §4): every rank holds a share of the points, the main rank
// the cameras and the global RCS. One process (LocalPointWorkers) and many
// MPI ranks (MpiPointWorkers) implement the same contract.
//
// Lifecycle (the LM loop is the one caller; the test fake in
// lm/lm_control_test.cc checks the order):
//   construct   the symbolic phase: RCS structure, scratch sized once
//   MakeDampedRcsSolver(system, options)  once, after the first FormRcs:
//               the linear solve's symbolic phase, where S lives
//   FormRcs(λ)  first call; then after every FinishStep that did not end the
//               solve; and once more after the solve's last FinishStep, with
//               λ = 0 and no step after it, to analyse the optimum
//               (lm/solve_with_priors.h's FormAtCurrentParameters). Linearizes and eliminates every point at the current
//               parameters (paper eq. 4) and returns the global RCS, its
//               right-hand side, gradient and cost, camera blocks undamped.
//               The system belongs to the workers and stays valid until the
//               next FormRcs; the caller may damp S in place.
//   EvaluateStep(λ, δc)  at most once per FormRcs, with the same λ: steps
//               the workers' own camera side to cameras ⊞ δc
//               (UnknownLayout::PlusCameraSide), back-substitutes every point
//               (eq. 5) into a candidate and returns the model and candidate
//               costs and norms, summed over all points.
//   FinishStep(accept)  exactly once after each EvaluateStep: accept makes
//               the candidate points and cameras current, otherwise they are
//               dropped. The caller steps its own x alike.
//   destroy     any time after a FinishStep or before the first
//               EvaluateStep; the points hold the last accepted values.
// Errors (a rank failing) are thrown from whichever call meets them.
//
// Thread safety: one caller (the LM loop); the work inside is threaded.
#pragma once

#include <vector>

#include "dba/lm/damped_rcs_solver.h"
#include "dba/rcs/back_substitute.h"
#include "dba/rcs/form_rcs.h"
#include "dba/rcs/pose_row_term.h"

namespace dba {

class PointWorkers {
 public:
  virtual ~PointWorkers() = default;

  // Global RCS at the current parameters and damping λ, cameras in global
  // numbering, S undamped in the camera blocks. The system is owned by the
  // workers and stays valid until the next call.
  virtual RcsSystem& FormRcs(double lambda) = 0;

  // Back-substitution and costs at cameras ⊞ δc (global numbering).
  virtual StepEvaluation EvaluateStep(double lambda, const std::vector<double>& delta_c) = 0;

  // Makes the candidate of the last EvaluateStep current (accept) or drops it.
  virtual void FinishStep(bool accept) = 0;

  // Where the system FormRcs returns holds no S (the RCS spread over the
  // ranks), the terms of residuals on camera poses alone (camera-centre
  // priors) for the next FormRcs to add, by their rows' owners; false (the
  // default): the caller adds them to the system FormRcs returns.
  virtual bool TakesPoseTerms() const { return false; }
  virtual void SetPoseTerms(std::vector<PoseRowTerm> terms) { (void)terms; }

  // The solver of (S + λ D_c) δc = b for the systems FormRcs returns
  // (`system`: the first); `choice` gets what was chosen and why. By
  // default the system holds all of S and is solved in place.
  virtual std::unique_ptr<DampedRcsSolver> MakeDampedRcsSolver(
      RcsSystem& system, const LinearSolverOptions& options, RcsSolverChoice* choice) {
    return std::make_unique<LocalDampedRcsSolver>(system.S, options, choice);
  }
};

}  // namespace dba
