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
// down by each rejection round). Walked once: the first Solve permutes it
// into the walk and it stays so through the rejection rounds (the next
// solves walk the kept points in the same order; a round renumbers only the
// cameras, as the kept points first see them) until EndSolves or AtOptimum
// puts it back in the order it was given. Between, the problem is in the
// walk's order and every figure the side hands out (points, cameras, what
// is kept, a round's poses) is mapped back to the order it was given.
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
  void EndSolves() override { GivenOrder(); }

 private:
  Problem* problem_;
  int64_t observations_, points_;  // as given
  std::vector<int64_t> walk_;      // over the points as given (until the first Solve)
  bool walked_ = false;            // the problem is in the walk's order
  // Walked: the problem's points as given, order_[k] the point (as given)
  // now at k (8 bytes per point; dropped at the first rejection round,
  // which keeps the map in origin_).
  std::vector<int64_t> order_;
  // Walked: the cameras in the order the walked points first see them,
  // camera_order_[i] the camera (as given) numbered i (8 bytes per camera).
  std::vector<int64_t> camera_order_;
  // From the first rejection round on (until then a solve pays nothing for
  // them: 8 bytes per observation and 32 per point): where each current
  // point and observation was in the problem as given, and every given
  // point's last values.
  bool cut_ = false;
  bool renumber_cameras_ = false;  // a round since the cameras were numbered
  OriginalIndices origin_;
  std::vector<double> all_;
  void WalkOrder();
  void NumberCamerasByWalk();
  void GivenOrder();
  CameraPriors WalkedPriors(const CameraPriors& priors) const;
  std::vector<int64_t> GivenPoints() const;
};

}  // namespace dba
