// LM with camera priors over any point side; see solve_with_priors.h.
#include "dba/lm/solve_with_priors.h"

#include <algorithm>

#include "dba/lm/prior_workers.h"

namespace dba {
namespace {

// x: the camera side's parameters, then the lever arm when refined.
std::vector<double> PriorsX(const std::vector<double>& cameras, const CameraPriors* priors) {
  std::vector<double> x = cameras;
  if (priors != nullptr && !priors->empty() && priors->refine_lever_arm) {
    x.insert(x.end(), priors->lever_arm.data(), priors->lever_arm.data() + 3);
  }
  return x;
}

}  // namespace

PriorSolve SolveWithPriors(const LmOptions& options, int64_t num_observations,
                           const CameraSide& side, std::vector<double>* cameras,
                           PointWorkers* points, const CameraPriors* priors,
                           const std::function<void(const IterationSummary&)>& on_iteration) {
  const bool with_priors = priors != nullptr && !priors->empty();
  const bool lever_arm = with_priors && priors->refine_lever_arm;
  PriorSolve solve;
  if (with_priors) solve.lever_arm = priors->lever_arm;
  // x: its own vector (one process's workers keep the problem's cameras
  // themselves, and the LM swaps x with its candidate).
  const size_t n = cameras->size();
  std::vector<double> x = PriorsX(*cameras, priors);
  auto write_back = [&] { std::copy(x.begin(), x.begin() + static_cast<int64_t>(n), cameras->begin()); };
  const std::function<void(const IterationSummary&)> hook = [&](const IterationSummary& it) {
    write_back();
    if (!on_iteration) return;
    IterationSummary with = it;
    if (lever_arm) with.lever_arm = Vec3(x.data() + n);
    on_iteration(with);
  };
  if (with_priors) {
    PriorWorkers prior_workers(points, &x, side, *priors);
    solve.lm = SolveLevenbergMarquardt(options, num_observations, &x, &prior_workers, hook);
  } else {
    solve.lm = SolveLevenbergMarquardt(options, num_observations, &x, points, hook);
  }
  write_back();
  if (lever_arm) solve.lever_arm = Vec3(x.data() + n);
  return solve;
}

void FormAtCurrentParameters(const CameraSide& side, PointWorkers* points,
                             const CameraPriors* priors,
                             const std::function<void(const RcsSystem&)>& look) {
  if (priors == nullptr || priors->empty()) {
    look(points->FormRcs(0.0));
    return;
  }
  std::vector<double> x = PriorsX(side.cameras, priors);
  PriorWorkers prior_workers(points, &x, side, *priors);
  look(prior_workers.FormRcs(0.0));
}

}  // namespace dba
