// One-process bundle adjustment; see bundle_adjust.h.
#include "dba/lm/bundle_adjust.h"

#include "dba/common/timer.h"
#include "dba/lm/local_point_workers.h"

namespace dba {

BundleAdjustSummary BundleAdjust(
    const LmOptions& options, Problem* problem,
    const std::function<void(const IterationSummary&)>& on_iteration,
    const std::function<void(const RcsSystem&)>& before_values, const CameraPriors* priors) {
  BundleAdjustSummary summary;
  Timer symbolic;
  const bool with_priors = priors != nullptr && !priors->empty();
  const bool lever_arm = with_priors && priors->refine_lever_arm;
  LocalPointWorkers workers(problem, options.damping, options.num_threads, options.loss,
                            before_values, false, lever_arm);
  summary.symbolic_seconds = symbolic.Seconds();
  summary.rcs = RcsFootprint::Of(workers.system().S);
  // x: the camera side, then the lever arm when it is an unknown.
  std::vector<double> cameras = problem->cameras;
  if (with_priors) {
    summary.lever_arm = priors->lever_arm;
    if (lever_arm) cameras.insert(cameras.end(), priors->lever_arm.data(), priors->lever_arm.data() + 3);
    PriorWorkers prior_workers(&workers, &cameras, *problem, *priors);
    // The hook sees the lever arm as the iteration left it (a checkpoint holds it).
    const size_t n = problem->cameras.size();
    const std::function<void(const IterationSummary&)> hook = [&](const IterationSummary& it) {
      if (!on_iteration) return;
      IterationSummary with = it;
      if (lever_arm) with.lever_arm = Vec3(cameras.data() + n);
      on_iteration(with);
    };
    summary.lm = SolveLevenbergMarquardt(options, problem->num_observations(), &cameras,
                                         &prior_workers, hook);
    if (lever_arm) summary.lever_arm = Vec3(cameras.data() + n);
  } else {
    summary.lm = SolveLevenbergMarquardt(options, problem->num_observations(), &cameras,
                                         &workers, on_iteration);
  }
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
