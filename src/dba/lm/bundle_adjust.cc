// One-process bundle adjustment; see bundle_adjust.h.
#include "dba/lm/bundle_adjust.h"

#include "dba/common/timer.h"
#include "dba/lm/local_point_workers.h"

namespace dba {

BundleAdjustSummary BundleAdjust(
    const LmOptions& options, Problem* problem,
    const std::function<void(const IterationSummary&)>& on_iteration,
    const std::function<void(const RcsSystem&)>& before_values) {
  BundleAdjustSummary summary;
  Timer symbolic;
  LocalPointWorkers workers(problem, options.damping, options.num_threads, options.loss,
                            before_values);
  summary.symbolic_seconds = symbolic.Seconds();
  const BsmcMatrix& S = workers.system().S;
  summary.rcs = {S.num_block_rows(), S.num_blocks(), S.num_rows(), S.StructureBytes(),
                 S.ValueBytes(), S.CsrBytes()};
  std::vector<double> cameras = problem->cameras;
  summary.lm = SolveLevenbergMarquardt(options, problem->num_observations(),
                                       &cameras, &workers, on_iteration);
  return summary;
}

}  // namespace dba
