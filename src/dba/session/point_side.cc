// Where a solve's points live; see point_side.h.
#include "dba/session/point_side.h"

namespace dba {

LocalPointSide::LocalPointSide(Problem* problem)
    : problem_(problem),
      observations_(problem->num_observations()),
      points_(problem->num_points()),
      original_(OriginalIndices::Identity(*problem)),
      all_(problem->points) {}

BundleAdjustSummary LocalPointSide::Solve(const LmOptions& options, const CameraPriors& priors,
                                          const IterationHook& hook,
                                          const std::function<void(const RcsSystem&)>& before_values) {
  return BundleAdjust(options, problem_, hook, before_values, &priors);
}

RejectionRound LocalPointSide::DropOutliers(const RejectionCriteria& criteria, int num_threads,
                                            bool) {
  AllPoints(&all_);
  return dba::DropOutliers(criteria, num_threads, problem_, &original_);
}

void LocalPointSide::AllPoints(std::vector<double>* points) {
  if (points != &all_) *points = all_;
  for (size_t k = 0; k < original_.point.size(); ++k) {
    for (int d = 0; d < kPointSize; ++d) {
      (*points)[kPointSize * original_.point[k] + d] = problem_->points[kPointSize * k + d];
    }
  }
  if (points != &all_) all_ = *points;
}

KeptObservations LocalPointSide::Kept() { return KeptFlags(original_, observations_, points_); }

void RankPointSide::AllPoints(std::vector<double>* points) {
  side_->CollectPoints(&points_);
  *points = points_;
}

}  // namespace dba
