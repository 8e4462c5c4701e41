// One-process bundle adjustment; see bundle_adjust.h.
#include "dba/lm/bundle_adjust.h"

#include "dba/common/timer.h"
#include "dba/lm/local_point_workers.h"
#include "dba/lm/solve_with_priors.h"

namespace dba {

BundleAdjustSummary BundleAdjust(
    const LmOptions& options, Problem* problem,
    const std::function<void(const IterationSummary&)>& on_iteration,
    const std::function<void(const RcsSystem&)>& before_values, const CameraPriors* priors) {
  BundleAdjustSummary summary;
  Timer symbolic;
  const bool lever_arm = priors != nullptr && !priors->empty() && priors->refine_lever_arm;
  LocalPointWorkers workers(problem, options.damping, options.num_threads, options.loss,
                            before_values, false, lever_arm);
  summary.symbolic_seconds = symbolic.Seconds();
  summary.rcs = RcsFootprint::Of(workers.system().S);
  PriorSolve solve = SolveWithPriors(options, problem->num_observations(), *problem,
                                     &problem->cameras, &workers, priors, on_iteration);
  summary.lm = std::move(solve.lm);
  summary.lever_arm = solve.lever_arm;
  return summary;
}

RcsFootprint RcsFootprint::Of(const BsmcMatrix& S) {
  return {S.num_block_rows(), S.num_blocks(), S.num_rows(), S.StructureBytes(), S.ValueBytes(),
          S.CsrBytes()};
}

// `total` followed by `next` (a solve after a rejection round): iterations,
// times and the log add up; the final state is next's.
void AppendSolve(const BundleAdjustSummary& next, BundleAdjustSummary* total) {
  LmSummary& t = total->lm;
  const LmSummary& n = next.lm;
  for (IterationSummary it : n.history) {
    it.iteration += t.iterations;
    t.history.push_back(it);
  }
  if (t.pcg_double_from_iteration == 0 && n.pcg_double_from_iteration > 0) {
    t.pcg_double_from_iteration = t.iterations + n.pcg_double_from_iteration;
  }
  t.iterations += n.iterations;
  t.accepted_iterations += n.accepted_iterations;
  t.total_linear_iterations += n.total_linear_iterations;
  t.times.rcs_formation += n.times.rcs_formation;
  t.times.linear_solve += n.times.linear_solve;
  t.times.back_substitution += n.times.back_substitution;
  t.times.total += n.times.total;
  t.final_cost = n.final_cost;
  t.final_residuals = n.final_residuals;
  t.num_observations = n.num_observations;
  t.termination = n.termination;
  t.termination_message = n.termination_message;
  total->symbolic_seconds += next.symbolic_seconds;
  total->rcs = next.rcs;
}

}  // namespace dba
