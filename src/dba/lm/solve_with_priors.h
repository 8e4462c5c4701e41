// The LM loop over any point side (lm/point_workers.h: one process's
// LocalPointWorkers or the ranks' MpiPointWorkers) with the camera priors'
// terms added (lm/prior_workers.h) and, when refined, their antenna's lever
// arm as three more unknowns (the layout's last row, rcs/unknown_layout.h):
//
//   x = [camera-side parameters, lever arm a]   (a only when refined)
//   LM over x (lm/levenberg_marquardt.h), the workers' candidates without a
//
// The one place both sides solve from, so that priors and the lever arm
// behave alike on one process and over ranks. The camera-side parameters
// are written back into `cameras` before each iteration's hook (a
// checkpoint reads them) and at the end; the hook's IterationSummary
// carries the lever arm as the iteration left it.
//
// Thread safety: one call per problem at a time.
#pragma once

#include <functional>
#include <vector>

#include "dba/lm/levenberg_marquardt.h"
#include "dba/lm/point_workers.h"
#include "dba/problem/problem.h"
#include "dba/rcs/camera_centre_prior.h"

namespace dba {

struct PriorSolve {
  LmSummary lm;
  Vec3 lever_arm = Vec3::Zero();  // the priors' (refined, when it is an unknown)
};

// LM from `cameras` (`side`'s camera-side parameters, which `side` may hold
// itself) over `points`, which must have been made with the lever arm's row
// when `priors` refine it (LocalPointWorkers' and UnknownLayout's flag).
// `priors` may be null or empty.
PriorSolve SolveWithPriors(const LmOptions& options, int64_t num_observations,
                           const CameraSide& side, std::vector<double>* cameras,
                           PointWorkers* points, const CameraPriors* priors,
                           const std::function<void(const IterationSummary&)>& on_iteration);

// The RCS at the current parameters, undamped (λ = 0: S = U - W V⁻¹ Wᵀ, the
// reduced camera matrix of the Gauss-Newton model, paper eq. 4), the
// priors' terms added as in a solve, handed to `look` while it is valid
// (the analysis of an optimum: docs/design.md §4.4). `points` as for
// SolveWithPriors; the RCS spread over ranks leaves S with its rows'
// owners (the system `look` gets then holds the layout and sums only).
void FormAtCurrentParameters(const CameraSide& side, PointWorkers* points,
                             const CameraPriors* priors,
                             const std::function<void(const RcsSystem&)>& look);

}  // namespace dba
