// One process's point side; see local_point_side.h.
#include "dba/lm/local_point_side.h"

#include <algorithm>
#include <numeric>
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
  WalkOrder();
  if (std::exchange(renumber_cameras_, false) && walked_) NumberCamerasByWalk();
  const CameraPriors walked = WalkedPriors(priors);
  return BundleAdjust(options, problem_, hook, before_values,
                      camera_order_.empty() ? &priors : &walked);
}

// The problem's points into the walk's order (the walk itself, or, put
// back after a rejection round, the kept points in the walk's order), and
// its cameras into the order the walked points first see them.
void LocalPointSide::WalkOrder() {
  if (walked_ || walk_.empty()) return;
  walked_ = true;
  if (!cut_) {
    order_.swap(walk_);
    PermutePoints(order_, problem_);
  } else {  // put back by AtOptimum, walked again: the kept points in walk order
    const std::vector<int64_t> place = InversePermutation(walk_);
    const int64_t n = problem_->num_points();
    std::vector<std::pair<int64_t, int64_t>> keyed(n);
    for (int64_t k = 0; k < n; ++k) keyed[k] = {place[origin_.point[k]], k};
    std::sort(keyed.begin(), keyed.end());
    std::vector<int64_t> order(n);
    for (int64_t k = 0; k < n; ++k) order[k] = keyed[k].second;
    PermutePoints(order, problem_);
    OriginalIndices walked;
    walked.point.resize(n);
    for (int64_t k = 0; k < n; ++k) walked.point[k] = origin_.point[order[k]];
    walked.observation.reserve(origin_.observation.size());
    std::vector<int64_t> first(n + 1, 0);  // the cut problem's offsets before the walk
    // (the walked problem's point k came from point order[k] with the same count)
    std::vector<int64_t> count(n);
    for (int64_t k = 0; k < n; ++k) count[order[k]] = problem_->point_offsets[k + 1] - problem_->point_offsets[k];
    for (int64_t k = 0; k < n; ++k) first[k + 1] = first[k] + count[k];
    for (int64_t k = 0; k < n; ++k) {
      for (int64_t j = first[order[k]]; j < first[order[k] + 1]; ++j) {
        walked.observation.push_back(origin_.observation[j]);
      }
    }
    origin_ = std::move(walked);
  }
  NumberCamerasByWalk();
}

// The cameras in the order the walked points first see them (composed with
// the numbering they had).
void LocalPointSide::NumberCamerasByWalk() {
  const std::vector<int64_t> order = CamerasInPointOrder(*problem_);
  PermuteCameras(order, problem_);
  if (camera_order_.empty()) {
    camera_order_ = order;
    return;
  }
  std::vector<int64_t> composed(order.size());
  for (size_t i = 0; i < order.size(); ++i) composed[i] = camera_order_[order[i]];
  camera_order_.swap(composed);
}

// Everything back in the order it was given (the kept points in their
// given order after rejection rounds).
void LocalPointSide::GivenOrder() {
  if (!walked_) return;
  walked_ = false;
  PermuteCameras(InversePermutation(camera_order_), problem_);
  std::vector<int64_t>().swap(camera_order_);
  if (!cut_) {
    PermutePoints(InversePermutation(order_), problem_);
    walk_.swap(order_);
    order_.clear();
    return;
  }
  // The kept points by their place as given; origin_ follows.
  const int64_t n = problem_->num_points();
  std::vector<int64_t> order(n);
  std::iota(order.begin(), order.end(), int64_t{0});
  std::sort(order.begin(), order.end(),
            [&](int64_t a, int64_t b) { return origin_.point[a] < origin_.point[b]; });
  std::vector<int64_t> observation;
  observation.reserve(origin_.observation.size());
  for (int64_t k : order) {
    for (int64_t o = problem_->point_offsets[k]; o < problem_->point_offsets[k + 1]; ++o) {
      observation.push_back(origin_.observation[o]);
    }
  }
  PermutePoints(order, problem_);
  std::sort(origin_.point.begin(), origin_.point.end());
  origin_.observation.swap(observation);
}

CameraPriors LocalPointSide::WalkedPriors(const CameraPriors& priors) const {
  CameraPriors walked = priors;
  if (camera_order_.empty()) return walked;
  const std::vector<int64_t> place = InversePermutation(camera_order_);
  for (CameraCentrePrior& p : walked.priors) p.image = static_cast<int32_t>(place[p.image]);
  return walked;
}

// Each current point's place as given.
std::vector<int64_t> LocalPointSide::GivenPoints() const {
  if (cut_) return origin_.point;
  if (!order_.empty()) return order_;
  std::vector<int64_t> identity(problem_->num_points());
  std::iota(identity.begin(), identity.end(), int64_t{0});
  return identity;
}

RejectionRound LocalPointSide::DropOutliers(const RejectionCriteria& criteria, int num_threads,
                                            bool, PoseObservations* poses) {
  if (!cut_) {
    AllPoints(&all_);
    OriginalIndices given;
    given.point = GivenPoints();
    // The given observations of each current point: a point keeps its
    // observations' order, and its count, through the walk.
    std::vector<int64_t> first(points_ + 1, 0);
    for (int64_t k = 0; k < problem_->num_points(); ++k) {
      first[given.point[k] + 1] = problem_->point_offsets[k + 1] - problem_->point_offsets[k];
    }
    for (int64_t g = 0; g < points_; ++g) first[g + 1] += first[g];
    given.observation.reserve(problem_->num_observations());
    for (int64_t k = 0; k < problem_->num_points(); ++k) {
      for (int64_t j = first[given.point[k]]; j < first[given.point[k] + 1]; ++j) {
        given.observation.push_back(j);
      }
    }
    origin_ = std::move(given);
    if (!order_.empty()) walk_ = std::move(order_);  // for a walk after AtOptimum
    order_.clear();
    cut_ = true;
  } else {
    AllPoints(&all_);
  }
  *poses = PoseObservations();
  poses->before.assign(problem_->num_frames(), 0);
  poses->after.assign(problem_->num_frames(), 0);
  CountPoseObservations(*problem_, {}, &poses->before);
  const RejectionRound round = dba::DropOutliers(criteria, num_threads, problem_, &origin_);
  CountPoseObservations(*problem_, {}, &poses->after);
  if (!problem_->has_rigs() && !camera_order_.empty()) poses->id = camera_order_;
  renumber_cameras_ = walked_;  // by the next Solve, as the kept points first see them
  return round;
}

void LocalPointSide::AllPoints(std::vector<double>* points) {
  const std::vector<int64_t> given = GivenPoints();
  std::vector<double> all = cut_ ? all_ : std::vector<double>(kPointSize * points_);
  for (size_t k = 0; k < given.size(); ++k) {
    std::copy_n(&problem_->points[kPointSize * k], kPointSize, &all[kPointSize * given[k]]);
  }
  *points = std::move(all);
}

void LocalPointSide::AllCameras(std::vector<double>* cameras) {
  *cameras = problem_->cameras;
  const int size = problem_->camera_size();
  for (size_t i = 0; i < camera_order_.size(); ++i) {
    std::copy_n(problem_->camera(static_cast<int64_t>(i)), size,
                cameras->data() + size * camera_order_[i]);
  }
}

// In the order it was given (the analysis reads S's rows so).
void LocalPointSide::AtOptimum(const LmOptions& options, const CameraPriors& priors,
                               const std::function<void(const RcsSystem&)>& look) {
  GivenOrder();
  LocalPointWorkers workers(problem_, options.damping, options.num_threads, options.loss, {},
                            false, !priors.empty() && priors.refine_lever_arm);
  FormAtCurrentParameters(*problem_, &workers, &priors, look);
}

KeptObservations LocalPointSide::Kept() {
  if (!cut_) return KeptFlags(OriginalIndices::Identity(*problem_), observations_, points_);
  return KeptFlags(origin_, observations_, points_);
}

}  // namespace dba
