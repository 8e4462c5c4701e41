// The LM loop; see levenberg_marquardt.h.
#include "dba/lm/levenberg_marquardt.h"

#include "dba/rcs/aggregation_order.h"
#include "dba/rcs/rigid_motion_basis.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "dba/common/interrupt.h"
#include "dba/common/timer.h"
#include "dba/lm/nielsen_damping.h"
#include "dba/lm/parameter_norm.h"

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

const char* TerminationMessage(TerminationReason reason) {
  switch (reason) {
    case TerminationReason::kFunctionTolerance: return "relative cost decrease below tolerance";
    case TerminationReason::kGradientTolerance: return "gradient max-norm below tolerance";
    case TerminationReason::kParameterTolerance: return "step size below tolerance";
    case TerminationReason::kMaxIterations: return "reached the iteration limit";
    case TerminationReason::kLambdaTooLarge: return "no acceptable step: damping too large";
  }
  return "unknown";
}

double LmSummary::Rms(double cost) const {
  return num_observations > 0 ? std::sqrt(2.0 * cost / num_observations) : 0.0;
}

namespace {

// Why the starting cost is nan or inf: a camera parameter that is (after
// an alignment, say), or else a residual.
std::string NonFiniteCause(const std::vector<double>& cameras) {
  for (size_t j = 0; j < cameras.size(); ++j) {
    if (!std::isfinite(cameras[j])) {
      return "camera parameter " + std::to_string(j) + " (camera-major) is " +
             std::to_string(cameras[j]) + " before the first iteration";
    }
  }
  return "a reprojection error or a camera prior's residual is nan or inf at the starting "
         "parameters (a point at infinity, a camera parameter that overflows its projection)";
}

// Gain ratios below this mark a poorly modelled step (see AcceptStep).
constexpr double kPoorModel = 0.25;

// One solve, each decision of the loop a named step. State: the RCS system
// at the current parameters (`sys_`, owned by the workers), its cost and
// residual sums, the damping, the linear solver (built once, at the first
// solve: S keeps its structure), and the scratch vectors δc and the
// candidate cameras, sized once.
class Minimizer {
 public:
  Minimizer(const LmOptions& options, int64_t num_observations, std::vector<double>* cameras,
            PointWorkers* workers, const std::function<void(const IterationSummary&)>& on_iteration)
      : options_(options),
        num_observations_(num_observations),
        cameras_(cameras),
        workers_(workers),
        on_iteration_(on_iteration),
        damping_(options.initial_lambda) {
    summary_.num_observations = num_observations;
    summary_.iterations = options.iterations_done;
    summary_.accepted_iterations = options.accepted_done;
  }

  LmSummary Run() {
    Linearize();
    CheckInitialCost();
    if (options_.ended) return EndedBefore(*options_.ended);
    // δc has one value per unknown (fixed parameters are not unknowns); the
    // candidate is cameras ⊞ δc (rcs/unknown_layout.h).
    delta_c_.resize(sys_->layout.num_unknowns());
    candidate_.resize(cameras_->size());
    for (bool done = false; !done;) {
      PollInterrupt();  // a host's request to stop (common/interrupt.h)
      if (ReachedIterationLimit()) break;
      Timer iteration_timer;
      IterationSummary it = StartIteration();
      if (GradientIsSmall(it)) break;
      const bool solved = SolveDampedRcs(&it);
      // A step whose RCS was not positive definite counts as rejected.
      const StepOutcome outcome = solved ? EvaluateStep(&it) : StepOutcome::kRejected;
      switch (outcome) {
        case StepOutcome::kTooSmall: done = DropTinyStep(&it); break;
        case StepOutcome::kAccepted: done = AcceptStep(it); break;
        case StepOutcome::kRejected: done = RejectStep(); break;
      }
      // The iteration that reaches the limit ends the solve itself, so that
      // its summary (and a checkpoint written from it) says so.
      if (!done) done = ReachedIterationLimit();
      // Next linearization: at the new point after an accepted step, with
      // the new λ after a rejected one.
      if (!done) Linearize();
      it.next_lambda = damping_.lambda();
      it.seconds = iteration_timer.Seconds();
      it.ends_solve = done;
      it.termination = summary_.termination;
      summary_.history.push_back(it);
      if (on_iteration_) on_iteration_(it);
    }
    summary_.final_cost = cost_;
    summary_.final_residuals = residuals_;
    summary_.times.total = total_timer_.Seconds();
    return summary_;
  }

 private:
  enum class StepOutcome { kAccepted, kRejected, kTooSmall };

  // A resumed solve that had ended: its cost at the checkpoint's
  // parameters, no iteration.
  LmSummary EndedBefore(const LmOptions::Ended& ended) {
    Terminate(ended.reason);
    summary_.final_cost = ended.cost;
    summary_.termination_message += " (when the checkpoint resumed from was written)";
    summary_.times.total = total_timer_.Seconds();
    return summary_;
  }

  // RCS, right-hand side, gradient and cost at the current parameters and λ.
  void Linearize() {
    Timer phase;
    sys_ = &workers_->FormRcs(damping_.lambda());
    summary_.times.rcs_formation += phase.Seconds();
    cost_ = sys_->cost;
    residuals_ = sys_->residuals;
  }

  void CheckInitialCost() {
    if (!std::isfinite(cost_)) {
      throw std::runtime_error("the initial cost is not finite (" + std::to_string(cost_) + "): " +
                               NonFiniteCause(*cameras_));
    }
    summary_.initial_cost = cost_;
    summary_.final_cost = cost_;
    summary_.initial_residuals = residuals_;
  }

  bool ReachedIterationLimit() {
    if (summary_.iterations < options_.max_iterations) return false;
    Terminate(TerminationReason::kMaxIterations);
    return true;
  }

  IterationSummary StartIteration() const {
    IterationSummary it;
    it.iteration = summary_.iterations + 1;
    it.cost = cost_;
    it.rms_pixels = LmSummary::Rms(residuals_.squared, static_cast<double>(num_observations_));
    it.lambda = damping_.lambda();
    it.gradient_max_norm = std::max(MaxAbs(sys_->camera_side_gradient), sys_->max_abs_point_gradient);
    return it;
  }

  bool GradientIsSmall(const IterationSummary& it) {
    if (it.gradient_max_norm > options_.gradient_tolerance) return false;
    Terminate(TerminationReason::kGradientTolerance);
    return true;
  }

  // Damps the camera blocks and solves S δc = b; false when S is not
  // numerically positive definite. Counts the iteration.
  bool SolveDampedRcs(IterationSummary* it) {
    Timer phase;
    if (!linear_solver_) linear_solver_ = MakeLinearSolver();
    // The first solve without the floor names its iteration in the report.
    if (floor_dropped_ && summary_.pcg_double_from_iteration == 0) {
      summary_.pcg_double_from_iteration = summary_.iterations + 1;
    }
    const LinearSolveSummary solve =
        linear_solver_->Solve(damping_.lambda(), options_.damping, sys_, delta_c_.data());
    it->linear_iterations = solve.iterations;
    it->linear_relative_residual = solve.relative_residual;
    it->linear_stop = solve.stop;
    summary_.total_linear_iterations += solve.iterations;
    summary_.times.linear_solve += phase.Seconds();
    ++summary_.iterations;
    return solve.ok;
  }

  // The symbolic phase of the linear solve, once per solve.
  std::unique_ptr<DampedRcsSolver> MakeLinearSolver() {
    LinearSolverOptions linear = LinearSolverOptionsFor(options_, num_observations_);
    if (linear.coarse_basis != CoarseBasis::kParameters &&
        linear.preconditioner == PreconditionerType::kTwoLevel) {
      linear.coarse_row_bases = RigidMotionBases(sys_->layout, cameras_->data(),
                                                 linear.coarse_basis == CoarseBasis::kSimilarity);
    }
    if (linear.preconditioner == PreconditionerType::kTwoLevel) {
      linear.aggregation_order = AggregationOrder(sys_->layout, cameras_->data());
    }
    std::unique_ptr<DampedRcsSolver> solver =
        workers_->MakeDampedRcsSolver(*sys_, linear, &summary_.linear_solver);
    summary_.linear_solver_bytes = solver->MemoryBytes();
    damping_.SetFloor(solver->min_lambda());
    // A resumed solve whose λ is at or under the floor had dropped it
    // before (the floor holds λ up exactly at it only to drop it).
    if (damping_.lambda() <= solver->min_lambda()) DropDampingFloor(solver.get());
    return solver;
  }

  // The damping floor of a mixed-precision product (solver/pcg.h) gone for
  // the rest of the solve, if the solver can drop it.
  void DropDampingFloor(DampedRcsSolver* solver) {
    if (!solver->DropDampingFloor()) return;
    damping_.SetFloor(solver->min_lambda());
    floor_dropped_ = true;
  }

  // Back-substitutes the points, evaluates the candidate's cost against the
  // model's (the gain ratio) and tells the workers whether to keep it.
  StepOutcome EvaluateStep(IterationSummary* it) {
    Timer phase;
    sys_->layout.Plus(cameras_->data(), delta_c_.data(), candidate_.data());
    const StepEvaluation eval = workers_->EvaluateStep(damping_.lambda(), delta_c_);
    candidate_residuals_ = eval.candidate_residuals;
    summary_.times.back_substitution += phase.Seconds();
    const double step_norm = std::sqrt(SquaredNorm(delta_c_) + eval.point_step_squared_norm);
    const double x_norm = ParameterNorm(sys_->layout, *cameras_, eval.point_spread);
    const double model_decrease = cost_ - eval.model_cost;
    it->candidate_cost = eval.candidate_cost;
    it->gain_ratio = model_decrease > 0 ? (cost_ - eval.candidate_cost) / model_decrease : 0.0;
    it->step_accepted = std::isfinite(eval.candidate_cost) && model_decrease > 0 &&
                        it->gain_ratio > options_.min_relative_decrease;
    const bool tiny =
        step_norm <= options_.parameter_tolerance * (x_norm + options_.parameter_tolerance);
    workers_->FinishStep(it->step_accepted && !tiny);
    if (tiny) return StepOutcome::kTooSmall;
    return it->step_accepted ? StepOutcome::kAccepted : StepOutcome::kRejected;
  }

  // A step below the parameter tolerance ends the solve; the parameters stay.
  bool DropTinyStep(IterationSummary* it) {
    it->step_accepted = false;
    Terminate(TerminationReason::kParameterTolerance);
    return true;
  }

  // Takes the candidate; true when the cost fell by less than the function
  // tolerance.
  bool AcceptStep(const IterationSummary& it) {
    cameras_->swap(candidate_);
    ++summary_.accepted_iterations;
    damping_.StepAccepted(it.gain_ratio);
    // A good step that the floor kept from lowering λ: the model holds at a
    // smaller damping than float's rounding of S allows.
    if (damping_.held_by_floor()) DropDampingFloor(linear_solver_.get());
    // Converged when the step lowered the cost by less than the tolerance,
    // unless the model was poor (ρ < 1/4, where a trust-region method shrinks
    // its region: Nocedal & Wright, Numerical Optimization, Algorithm 4.1)
    // and promised more (decrease / ρ above the tolerance): such a step
    // says the model failed there, not that the optimum is near. Near the
    // optimum, where ρ is mostly rounding, the model promises nothing.
    const double decrease = cost_ - it.candidate_cost;
    const double tolerance = options_.function_tolerance * cost_;
    const bool poor_model = it.gain_ratio < kPoorModel && decrease > tolerance * it.gain_ratio;
    const bool converged = decrease <= tolerance && !poor_model;
    if (converged) {
      Terminate(TerminationReason::kFunctionTolerance);
    }
    cost_ = it.candidate_cost;
    residuals_ = candidate_residuals_;
    return converged;
  }

  // Raises the damping; true when it passed its limit.
  bool RejectStep() {
    damping_.StepRejected();
    if (damping_.lambda() <= options_.max_lambda) return false;
    Terminate(TerminationReason::kLambdaTooLarge);
    return true;
  }

  void Terminate(TerminationReason reason) {
    summary_.termination = reason;
    summary_.termination_message = TerminationMessage(reason);
  }

  const LmOptions& options_;
  const int64_t num_observations_;
  std::vector<double>* cameras_;
  PointWorkers* workers_;
  const std::function<void(const IterationSummary&)>& on_iteration_;
  NielsenDamping damping_;
  Timer total_timer_;
  LmSummary summary_;
  RcsSystem* sys_ = nullptr;
  double cost_ = 0.0;       // at the current parameters
  ResidualSums residuals_;  // at the current parameters
  ResidualSums candidate_residuals_;
  std::unique_ptr<DampedRcsSolver> linear_solver_;
  bool floor_dropped_ = false;  // DampedRcsSolver::DropDampingFloor said yes
  std::vector<double> delta_c_, candidate_;
};

}  // namespace

LinearSolverOptions LinearSolverOptionsFor(const LmOptions& options, int64_t num_observations) {
  LinearSolverOptions linear = options.linear_solver;
  linear.num_threads = options.num_threads;
  linear.num_observations = num_observations;
  // Observations (camera index, pixel), parameters, point offsets: about
  // 29 bytes per observation over the problems measured (bench/README.md).
  linear.problem_bytes = 29 * num_observations;
  return linear;
}

LmSummary SolveLevenbergMarquardt(
    const LmOptions& options, int64_t num_observations, std::vector<double>* cameras,
    PointWorkers* workers, const std::function<void(const IterationSummary&)>& on_iteration) {
  return Minimizer(options, num_observations, cameras, workers, on_iteration).Run();
}

}  // namespace dba
