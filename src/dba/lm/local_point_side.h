// One process's point side (lm/point_side.h): the problem itself, its
// points walked in a spatial order during each solve and its points and
// observations cut down by each rejection round.
//
// Thread safety: one caller.
#pragma once

#include <functional>
#include <vector>

#include "dba/lm/point_side.h"

namespace dba {

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

}  // namespace dba
