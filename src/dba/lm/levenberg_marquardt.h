// The exact Levenberg-Marquardt loop (paper eq. 1, docs/design.md §1):
//
//   (JᵀJ + λ D) δ = -Jᵀ r,   D = clamp(diag JᵀJ)
//
// solved through the RCS (eq. 4) by the linear solver of solver/rcs_solver.h
// (a dense or sparse Cholesky factorization, or truncated-Newton PCG, eq. 6-7)
// and point back-substitution (eq. 5). An RCS that is not positive definite
// counts as a rejected step. Step control is a trust region on λ: the gain ratio
//   ρ = (F(x) - F(x + δ)) / (F(x) - L(δ)),  L(δ) = ½ |r + J δ|²
// accepts the step when ρ > min_relative_decrease; λ follows Nielsen's update
// (lm/nielsen_damping.h). The loop itself (levenberg_marquardt.cc) is a
// Minimizer whose steps are named: Linearize, SolveDampedRcs, EvaluateStep,
// then AcceptStep, RejectStep or DropTinyStep, each ending the solve when its
// stopping rule holds.
//
// Thread safety: one solve at a time per PointWorkers.
#pragma once

#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "dba/lm/point_workers.h"
#include "dba/rcs/eliminate_point.h"
#include "dba/solver/rcs_solver.h"

namespace dba {

enum class TerminationReason {
  kFunctionTolerance,
  kGradientTolerance,
  kParameterTolerance,
  kMaxIterations,
  kLambdaTooLarge,  // no acceptable step found with ever stronger damping
};
const char* TerminationReasonName(TerminationReason reason);
// The log's words for why a solve ended ("relative cost decrease below
// tolerance").
const char* TerminationMessage(TerminationReason reason);

struct LmOptions {
  // Upper bound on LM iterations (accepted and rejected steps both count).
  int max_iterations = 100;
  // Stop when an accepted step lowers the cost by less than this fraction
  // (unless its model was poor: levenberg_marquardt.cc, AcceptStep).
  double function_tolerance = 1e-6;
  // Stop when ‖g‖∞ ≤ gradient_tolerance, g = Jᵀ r.
  double gradient_tolerance = 1e-10;
  // Stop when ‖δ‖ ≤ parameter_tolerance (‖x‖ + parameter_tolerance), ‖x‖
  // with the cameras' centres and the points about their centroids
  // (lm/parameter_norm.h).
  double parameter_tolerance = 1e-8;
  // Initial damping λ (Ceres's initial trust region radius 1e4 is λ = 1e-4).
  double initial_lambda = 1e-4;
  // Give up when λ grows past this after repeated rejections.
  double max_lambda = 1e16;
  // A step is accepted when ρ exceeds this.
  double min_relative_decrease = 1e-3;
  DampingBounds damping;
  // The cost is ½ Σ ρ(|r|²) (rcs/robust_loss.h); default the squared loss.
  RobustLoss loss;
  LinearSolverOptions linear_solver;
  int num_threads = 1;
  // A resumed solve (io/checkpoint.h): the iterations an earlier run did,
  // counted toward max_iterations and in the log's numbering. initial_lambda
  // is then the checkpoint's.
  int iterations_done = 0;
  int accepted_done = 0;
  // A resumed solve whose checkpoint was written by the step that ended it:
  // no iteration is taken, and it ends as it did, at the cost that step
  // reported (the checkpoint's; evaluating it again sums in another order).
  struct Ended {
    TerminationReason reason;
    double cost;
  };
  std::optional<Ended> ended;
};



struct IterationSummary {
  int iteration = 0;
  double cost = 0.0;           // at the start of the iteration
  double rms_pixels = 0.0;     // plain RMS over all observations
  double gradient_max_norm = 0.0;
  double lambda = 0.0;         // damping used for this step
  int linear_iterations = 0;          // PCG iterations (0: factorized)
  double linear_relative_residual = 0.0;
  std::string linear_stop;            // why the linear solve stopped
  double candidate_cost = 0.0;
  double gain_ratio = 0.0;
  bool step_accepted = false;
  double next_lambda = 0.0;    // the damping after this step's outcome
  double seconds = 0.0;        // wall time of this iteration
  // This iteration ended the solve, for `termination` (a checkpoint written
  // after it says so: io/checkpoint.h).
  bool ends_solve = false;
  TerminationReason termination = TerminationReason::kMaxIterations;
  // The camera priors' lever arm after this iteration, when it is an
  // unknown (lm/bundle_adjust.h fills it in what its hook sees).
  Vec3 lever_arm = Vec3::Zero();
};

struct PhaseTimes {
  double rcs_formation = 0.0;     // linearization, elimination, aggregation
  double linear_solve = 0.0;      // damping, factorization or PCG
  double back_substitution = 0.0; // back-substitution and step evaluation
  double total = 0.0;
};

struct LmSummary {
  double initial_cost = 0.0;  // ½ Σ ρ(|r|²)
  double final_cost = 0.0;
  // Plain squared residuals at the start and at the end (RMS over all
  // observations and over the loss's inliers).
  ResidualSums initial_residuals, final_residuals;
  int64_t num_observations = 0;
  int iterations = 0;
  int accepted_iterations = 0;
  int total_linear_iterations = 0;
  RcsSolverChoice linear_solver;  // which solver, and why
  int64_t linear_solver_bytes = 0;
  // The LM iteration from which PCG's product was in double, the damping
  // floor dropped (RcsSolver::DropDampingFloor); 0: never.
  int pcg_double_from_iteration = 0;
  TerminationReason termination = TerminationReason::kMaxIterations;
  std::string termination_message;
  PhaseTimes times;
  std::vector<IterationSummary> history;

  double Rms(double cost) const;  // sqrt(2 F / num_observations)
  static double Rms(double squared_sum, double count) {
    return count > 0 ? std::sqrt(squared_sum / count) : 0.0;
  }
};

// The linear solver's options for a solve of `num_observations` with
// `options` (threads, and the sizes auto's cost model and budget weigh).
LinearSolverOptions LinearSolverOptionsFor(const LmOptions& options, int64_t num_observations);

// Runs LM on the workers' points with `cameras` (global numbering, the
// camera-side parameters) as the main node's copy of the cameras, updated in place.
// `on_iteration` (optional) is called once per iteration, e.g. to log.
LmSummary SolveLevenbergMarquardt(
    const LmOptions& options, int64_t num_observations,
    std::vector<double>* cameras, PointWorkers* workers,
    const std::function<void(const IterationSummary&)>& on_iteration = {});

}  // namespace dba
