// The LM loop; see levenberg_marquardt.h.
#include "dba/lm/levenberg_marquardt.h"

#include "dba/rcs/rigid_motion_basis.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "dba/common/timer.h"

namespace dba {
namespace {

double SquaredNorm(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return s;
}

double MaxAbs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

// Nielsen: a rejected step multiplies λ by ν and doubles ν.
void RejectStep(double* lambda, double* nu) {
  *lambda *= *nu;
  *nu *= 2.0;
}

}  // namespace

const char* TerminationReasonName(TerminationReason reason) {
  switch (reason) {
    case TerminationReason::kFunctionTolerance: return "function_tolerance";
    case TerminationReason::kGradientTolerance: return "gradient_tolerance";
    case TerminationReason::kParameterTolerance: return "parameter_tolerance";
    case TerminationReason::kMaxIterations: return "max_iterations";
    case TerminationReason::kLambdaTooLarge: return "lambda_too_large";
  }
  return "unknown";
}

double LmSummary::Rms(double cost) const {
  return num_observations > 0 ? std::sqrt(2.0 * cost / num_observations) : 0.0;
}

LmSummary SolveLevenbergMarquardt(
    const LmOptions& options, int64_t num_observations,
    std::vector<double>* cameras, PointWorkers* workers,
    const std::function<void(const IterationSummary&)>& on_iteration) {
  LmSummary summary;
  summary.num_observations = num_observations;
  Timer total_timer;
  double lambda = options.initial_lambda;
  double nu = 2.0;

  Timer phase;
  RcsSystem* sys = &workers->FormRcs(lambda);
  summary.times.rcs_formation += phase.Seconds();
  double cost = sys->cost;
  if (!std::isfinite(cost)) {
    throw std::runtime_error("the initial cost is not finite (" + std::to_string(cost) +
                             "): some observation's reprojection error is nan or inf");
  }
  summary.initial_cost = cost;
  summary.final_cost = cost;
  summary.initial_residuals = sys->residuals;
  ResidualSums residuals = sys->residuals;  // at the current parameters

  // δc has one value per unknown (fixed parameters are not unknowns); the
  // candidate is cameras ⊞ δc (rcs/unknown_layout.h).
  std::vector<double> delta_c(sys->layout.num_unknowns()), candidate(cameras->size());
  std::unique_ptr<RcsSolver> linear_solver;
  bool done = false;
  while (!done) {
    if (summary.iterations >= options.max_iterations) {
      summary.termination = TerminationReason::kMaxIterations;
      summary.termination_message = "reached the iteration limit";
      break;
    }
    Timer iteration_timer;
    IterationSummary it;
    it.iteration = summary.iterations + 1;
    it.cost = cost;
    it.rms_pixels = LmSummary::Rms(residuals.squared, static_cast<double>(num_observations));
    it.lambda = lambda;
    it.gradient_max_norm =
        std::max(MaxAbs(sys->camera_gradient), sys->max_abs_point_gradient);
    if (it.gradient_max_norm <= options.gradient_tolerance) {
      summary.termination = TerminationReason::kGradientTolerance;
      summary.termination_message = "gradient max-norm below tolerance";
      break;
    }

    // Camera damping, then the linear solve of the damped RCS.
    phase.Reset();
    DampCameraBlocks(lambda, options.damping, sys->camera_jtj_diagonal, &sys->S);
    if (!linear_solver) {  // symbolic phase, once: S keeps its structure
      LinearSolverOptions linear = options.linear_solver;
      linear.num_threads = options.num_threads;
      linear.num_observations = num_observations;
      // Observations (camera index, pixel), parameters, point offsets: about
      // 29 bytes per observation over the problems measured (bench/README.md).
      linear.problem_bytes = 29 * num_observations;
      if (linear.rigid_coarse_basis && linear.preconditioner == PreconditionerType::kTwoLevel) {
        linear.coarse_row_bases = RigidMotionBases(sys->layout, cameras->data());
      }
      linear_solver = MakeRcsSolver(sys->S, linear, &summary.linear_solver);
      summary.linear_solver_bytes = linear_solver->MemoryBytes();
    }
    const LinearSolveSummary solve = linear_solver->Solve(sys->S, sys->b.data(), delta_c.data());
    it.linear_iterations = solve.iterations;
    it.linear_relative_residual = solve.relative_residual;
    it.linear_stop = solve.stop;
    summary.total_linear_iterations += solve.iterations;
    summary.times.linear_solve += phase.Seconds();
    ++summary.iterations;

    // Back-substitution and evaluation of the step (none when S was not
    // positive definite: that counts as a rejected step).
    bool small_step = false;
    ResidualSums candidate_residuals;
    if (solve.ok) {
      phase.Reset();
      sys->layout.Plus(cameras->data(), delta_c.data(), candidate.data());
      const StepEvaluation eval = workers->EvaluateStep(lambda, delta_c, candidate);
      candidate_residuals = eval.candidate_residuals;
      summary.times.back_substitution += phase.Seconds();
      const double step_norm = std::sqrt(SquaredNorm(delta_c) + eval.point_step_squared_norm);
      const double x_norm = std::sqrt(SquaredNorm(*cameras) + eval.point_squared_norm);
      const double model_decrease = cost - eval.model_cost;
      it.candidate_cost = eval.candidate_cost;
      it.gain_ratio = model_decrease > 0 ? (cost - eval.candidate_cost) / model_decrease : 0.0;
      it.step_accepted = std::isfinite(eval.candidate_cost) && model_decrease > 0 &&
                         it.gain_ratio > options.min_relative_decrease;
      small_step =
          step_norm <= options.parameter_tolerance * (x_norm + options.parameter_tolerance);
      workers->FinishStep(it.step_accepted && !small_step);
    }

    if (small_step) {
      it.step_accepted = false;  // dropped: the parameters stay where they are
      summary.termination = TerminationReason::kParameterTolerance;
      summary.termination_message = "step size below tolerance";
      done = true;
    } else if (it.step_accepted) {
      cameras->swap(candidate);
      ++summary.accepted_iterations;
      const double r = 2.0 * it.gain_ratio - 1.0;
      lambda *= std::max(1.0 / 3.0, 1.0 - r * r * r);
      nu = 2.0;
      if (cost - it.candidate_cost <= options.function_tolerance * cost) {
        summary.termination = TerminationReason::kFunctionTolerance;
        summary.termination_message = "relative cost decrease below tolerance";
        done = true;
      }
      cost = it.candidate_cost;
      residuals = candidate_residuals;
    } else {
      RejectStep(&lambda, &nu);
      if (lambda > options.max_lambda) {
        summary.termination = TerminationReason::kLambdaTooLarge;
        summary.termination_message = "no acceptable step: damping too large";
        done = true;
      }
    }

    if (!done) {
      // Next linearization: at the new point after an accepted step, with
      // the new λ after a rejected one.
      phase.Reset();
      sys = &workers->FormRcs(lambda);
      summary.times.rcs_formation += phase.Seconds();
      cost = sys->cost;
      residuals = sys->residuals;
    }
    it.seconds = iteration_timer.Seconds();
    summary.history.push_back(it);
    if (on_iteration) on_iteration(it);
  }
  summary.final_cost = cost;
  summary.final_residuals = residuals;
  summary.times.total = total_timer.Seconds();
  return summary;
}

}  // namespace dba
