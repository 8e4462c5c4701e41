// One process's point side; see local_point_side.h.
#include "dba/lm/local_point_side.h"

#include <algorithm>
#include <utility>

#include "dba/lm/local_point_workers.h"
#include "dba/lm/solve_with_priors.h"
#include "dba/problem/point_order.h"

namespace dba {

LocalPointSide::LocalPointSide(Problem* problem, std::vector<int64_t> walk)
    : problem_(problem),
      observations_(problem->num_observations()),
      points_(problem->num_points()),
      walk_(std::move(walk)) {}

BundleAdjustSummary LocalPointSide::Solve(const LmOptions& options, const CameraPriors& priors,
                                          const IterationHook& hook,
                                          const std::function<void(const RcsSystem&)>& before_values) {
  WalkOrder(priors);
  BundleAdjustSummary s;
  try {
    s = BundleAdjust(options, problem_, hook, before_values,
                     camera_order_.empty() ? &priors : &walked_priors_);
  } catch (...) {
    GivenOrder();
    throw;
  }
  GivenOrder();
  return s;
}

// The problem's points into the walk's order (the walk itself, or after a
// rejection round the kept points in the walk's order), and its cameras
// into the order the walked points first see them (a sequential pass), with
// the priors' images.
void LocalPointSide::WalkOrder(const CameraPriors& priors) {
  if (walk_.empty()) return;
  if (!cut_) {
    order_.swap(walk_);
  } else {
    const std::vector<int64_t> place = InversePermutation(walk_);
    const int64_t n = problem_->num_points();
    std::vector<std::pair<int64_t, int64_t>> keyed(n);
    for (int64_t k = 0; k < n; ++k) keyed[k] = {place[original_.point[k]], k};
    std::sort(keyed.begin(), keyed.end());
    order_.resize(n);
    for (int64_t k = 0; k < n; ++k) order_[k] = keyed[k].second;
  }
  PermutePoints(order_, problem_);
  camera_order_ = CamerasInPointOrder(*problem_);
  PermuteCameras(camera_order_, problem_);
  walked_priors_ = priors;
  const std::vector<int64_t> place = InversePermutation(camera_order_);
  for (CameraCentrePrior& p : walked_priors_.priors) p.image = static_cast<int32_t>(place[p.image]);
}

void LocalPointSide::GivenOrder() {
  if (order_.empty()) return;
  PermuteCameras(InversePermutation(camera_order_), problem_);
  std::vector<int64_t>().swap(camera_order_);
  walked_priors_ = CameraPriors();
  PermutePoints(InversePermutation(order_), problem_);
  if (walk_.empty()) walk_.swap(order_);
  order_.clear();
}

RejectionRound LocalPointSide::DropOutliers(const RejectionCriteria& criteria, int num_threads,
                                            bool, PoseObservations* poses) {
  if (!cut_) {
    original_ = OriginalIndices::Identity(*problem_);
    all_ = problem_->points;
    cut_ = true;
  } else {
    AllPoints(&all_);
  }
  *poses = PoseObservations();
  poses->before.assign(problem_->num_frames(), 0);
  poses->after.assign(problem_->num_frames(), 0);
  CountPoseObservations(*problem_, {}, &poses->before);
  const RejectionRound round = dba::DropOutliers(criteria, num_threads, problem_, &original_);
  CountPoseObservations(*problem_, {}, &poses->after);
  return round;
}

void LocalPointSide::AllPoints(std::vector<double>* points) {
  // Inside a solve the points are in the walk's order: as the solve was
  // given them first.
  std::vector<double> given;
  const std::vector<double>* now = &problem_->points;
  if (!order_.empty()) {
    given.resize(problem_->points.size());
    for (size_t k = 0; k < order_.size(); ++k) {
      std::copy_n(&problem_->points[kPointSize * k], kPointSize, &given[kPointSize * order_[k]]);
    }
    now = &given;
  }
  if (!cut_) {
    *points = *now;
    return;
  }
  if (points != &all_) *points = all_;
  for (size_t k = 0; k < original_.point.size(); ++k) {
    for (int d = 0; d < kPointSize; ++d) {
      (*points)[kPointSize * original_.point[k] + d] = (*now)[kPointSize * k + d];
    }
  }
  if (points != &all_) all_ = *points;
}

void LocalPointSide::AllCameras(std::vector<double>* cameras) {
  *cameras = problem_->cameras;
  const int size = problem_->camera_size();
  for (size_t i = 0; i < camera_order_.size(); ++i) {
    std::copy_n(problem_->camera(static_cast<int64_t>(i)), size,
                cameras->data() + size * camera_order_[i]);
  }
}

// Between solves the problem is in the order it was given (GivenOrder).
void LocalPointSide::AtOptimum(const LmOptions& options, const CameraPriors& priors,
                               const std::function<void(const RcsSystem&)>& look) {
  LocalPointWorkers workers(problem_, options.damping, options.num_threads, options.loss, {},
                            false, !priors.empty() && priors.refine_lever_arm);
  FormAtCurrentParameters(*problem_, &workers, &priors, look);
}

KeptObservations LocalPointSide::Kept() {
  if (!cut_) return KeptFlags(OriginalIndices::Identity(*problem_), observations_, points_);
  return KeptFlags(original_, observations_, points_);
}

}  // namespace dba
