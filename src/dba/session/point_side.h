// Where a solve's points live while the session runs LM and the rejection
// rounds over them: in this process (LocalPointSide), or spread over MPI
// ranks (RankPointSide, over cluster/distributed_solve.h's
// DistributedPointSide; the other ranks serve theirs meanwhile). The
// session sees one interface and writes one code path for both.
//
// Numbering: what the side was given (the problem as handed to it).
//
// Thread safety: one caller (the main rank).
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "dba/cluster/distributed_solve.h"
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
};

// One process: the problem itself (its points and observations are cut
// down by each rejection round).
class LocalPointSide : public PointSide {
 public:
  // `walk`: the order the solves walk the points in (problem/point_order.h;
  // walk[k] the point of `problem` walked k-th), fixed at the load so that
  // a resumed solve walks them as the uninterrupted one did (8 bytes per
  // point); empty: the problem's own order.
  // A walked solve numbers the cameras as the walked points first see them.
  LocalPointSide(Problem* problem, std::vector<int64_t> walk);
  BundleAdjustSummary Solve(const LmOptions& options, const CameraPriors& priors,
                            const IterationHook& hook,
                            const std::function<void(const RcsSystem&)>& before_values) override;
  RejectionRound DropOutliers(const RejectionCriteria& criteria, int num_threads,
                              bool keep_loss, PoseObservations* poses) override;
  void AllPoints(std::vector<double>* points) override;
  KeptObservations Kept() override;
  void AllCameras(std::vector<double>* cameras) override;
  void AtOptimum(const LmOptions& options, const CameraPriors& priors,
                 const std::function<void(const RcsSystem&)>& look) override;

 private:
  Problem* problem_;
  int64_t observations_, points_;  // as given
  // From the first rejection round on (until then the problem is as given,
  // and a solve without rejection pays nothing for them: 8 bytes per
  // observation and 32 per point):
  bool cut_ = false;
  OriginalIndices original_;       // current -> as given
  std::vector<double> all_;        // every point as given, the kept ones' last values
  std::vector<int64_t> walk_;      // over the points as given (moved to order_ in a solve)
  // During a solve: the problem's points in the walk's order, order_[k] the
  // point (as the solve was given it) now at k; empty between solves.
  std::vector<int64_t> order_;
  // During a walked solve: the cameras in the order the walked points first
  // see them, camera_order_[i] the camera (as given) numbered i (8 bytes per
  // camera), and the priors' images renumbered alike; empty otherwise.
  std::vector<int64_t> camera_order_;
  CameraPriors walked_priors_;
  void WalkOrder(const CameraPriors& priors);
  void GivenOrder();
};

// N ranks, as the main rank drives them.
class RankPointSide : public PointSide {
 public:
  RankPointSide(std::unique_ptr<DistributedPointSide> side, const Problem* problem)
      : side_(std::move(side)), problem_(problem) {}
  BundleAdjustSummary Solve(const LmOptions& options, const CameraPriors& priors,
                            const IterationHook& hook,
                            const std::function<void(const RcsSystem&)>&) override {
    return side_->Solve(options, priors, hook);
  }
  RejectionRound DropOutliers(const RejectionCriteria& criteria, int num_threads,
                              bool keep_loss, PoseObservations* poses) override {
    return side_->DropOutliers(criteria, num_threads, keep_loss, poses);
  }
  void AllPoints(std::vector<double>* points) override;
  KeptObservations Kept() override { return side_->Kept(); }
  void AllCameras(std::vector<double>* cameras) override { *cameras = problem_->cameras; }
  void AtOptimum(const LmOptions& options, const CameraPriors& priors,
                 const std::function<void(const RcsSystem&)>& look) override {
    side_->AtOptimum(options, priors, look);
  }
  DistributedPointSide& distributed() { return *side_; }

 private:
  std::unique_ptr<DistributedPointSide> side_;
  const Problem* problem_;  // the main rank's: its cameras
  std::vector<double> points_;  // collected: dropped points keep their values
};

}  // namespace dba
