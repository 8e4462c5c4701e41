// Where a solve's points live while the session runs LM and the rejection
// rounds over them: in this process (lm/local_point_side.h), or spread
// over MPI ranks (cluster/distributed_solve.h's DistributedPointSide; the
// other ranks serve theirs meanwhile). The session sees one interface and
// writes one code path for both; both solve through lm/solve_with_priors.h
// (the camera priors and their lever arm in one place).
//
// Numbering: what the side was given (the problem as handed to it).
//
// Thread safety: one caller (the main rank).
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "dba/lm/bundle_adjust.h"
#include "dba/lm/outlier_rejection.h"
#include "dba/lm/rejection_guard.h"
#include "dba/rcs/camera_centre_prior.h"

namespace dba {

class PointSide {
 public:
  using IterationHook = std::function<void(const IterationSummary&)>;
  virtual ~PointSide() = default;
  // LM from the current parameters with `options` (its loss), the priors'
  // terms added; `before_values` (if any) sees the RCS structure first.
  virtual BundleAdjustSummary Solve(const LmOptions& options, const CameraPriors& priors,
                                    const IterationHook& hook,
                                    const std::function<void(const RcsSystem&)>& before_values) = 0;
  // One round of rejection at the current parameters; the next Solve works
  // on what is left (with --loss kept, or the squared one). Each pose's
  // observations before and after it into `poses` (lm/rejection_guard.h).
  virtual RejectionRound DropOutliers(const RejectionCriteria& criteria, int num_threads,
                                      bool keep_loss, PoseObservations* poses) = 0;
  // Every point the side was given (those dropped with their last values),
  // and what is left of them and of their observations.
  virtual void AllPoints(std::vector<double>* points) = 0;
  virtual KeptObservations Kept() = 0;
  // The camera-side parameters as the side was given them (inside a solve
  // too: a checkpoint's).
  virtual void AllCameras(std::vector<double>* cameras) = 0;
  // After the last Solve, ranks alive: the RCS at the optimum (λ = 0, the
  // priors' terms added: lm/solve_with_priors.h) handed to `look`, its rows
  // in the numbering the side was given.
  virtual void AtOptimum(const LmOptions& options, const CameraPriors& priors,
                         const std::function<void(const RcsSystem&)>& look) = 0;
  // After the last Solve: the problem handed to the side back in the order
  // it was given (a local side keeps its walk's from the first Solve on).
  virtual void EndSolves() {}
};

}  // namespace dba
