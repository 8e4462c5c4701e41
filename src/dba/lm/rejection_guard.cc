// The guard of --reject-outliers; see rejection_guard.h.
#include "dba/lm/rejection_guard.h"

#include <algorithm>
#include <cstdio>
#include <cstring>

namespace dba {

void CountPoseObservations(const Problem& problem, std::span<const int32_t> pose,
                           std::vector<int64_t>* counts) {
  for (int64_t o = 0; o < problem.num_observations(); ++o) {
    const int64_t image = problem.obs_camera[o];
    const int64_t frame = problem.has_rigs() ? problem.image_frame[image] : image;
    const int64_t p = pose.empty() ? frame : pose[frame];
    if (p >= static_cast<int64_t>(counts->size())) counts->resize(p + 1, 0);
    ++(*counts)[p];
  }
}

int MinPoseObservations(CameraModel model) {
  return model == CameraModel::kBal ? (kBalCameraSize + 1) / 2 : kPhotoPoseSize / 2;
}

namespace {

// Why the solve before the round may not have settled.
std::string LikelyCause(const SolveBeforeRound& before) {
  const bool limit = before.termination == TerminationReason::kMaxIterations;
  const char* why = before.squared && limit
                        ? "had the squared loss, which mismatches drag, and stopped at "
                          "--max-iterations unconverged"
                    : before.squared ? "had the squared loss, which mismatches drag"
                    : limit          ? "stopped at --max-iterations unconverged"
                                     : "did not settle on the inliers";
  return std::string("the solve before it ") + why +
         ", the threshold is below the noise, or that many are mismatches";
}

// The free poses the round leaves with fewer than `least` observations that
// had at least that many.
std::vector<int64_t> Undetermined(const PoseObservations& poses, const Problem& side, int least) {
  std::vector<uint8_t> fixed(poses.before.size(), 0);
  for (int64_t i = 0; i < side.num_images(); ++i) {
    const int64_t f = side.has_rigs() ? side.image_frame[i] : i;
    if (side.camera_fixed(i) && f < static_cast<int64_t>(fixed.size())) fixed[f] = 1;
  }
  std::vector<int64_t> left;
  for (size_t f = 0; f < poses.before.size(); ++f) {
    const int64_t after = f < poses.after.size() ? poses.after[f] : 0;
    if (!fixed[f] && poses.before[f] >= least && after < least) left.push_back(f);
  }
  return left;
}

}  // namespace

void CheckRejectionRound(const RejectionGuard& guard, double max_error_px, int r,
                         const RejectionRound& round, const PoseObservations& poses,
                         const Problem& side, const SolveBeforeRound& before) {
  if (guard.max_share >= 1.0) return;
  const int64_t started = round.observations_dropped + round.observations_left;
  const double share = started > 0 ? static_cast<double>(round.observations_dropped) / started : 0;
  char head[300];
  std::snprintf(head, sizeof head,
                "outlier rejection round %d (|r| > %g px) would drop %lld of %lld observations "
                "(%.1f%%",
                r, max_error_px, static_cast<long long>(round.observations_dropped),
                static_cast<long long>(started), 100.0 * share);
  if (round.points_small_angle > 0) {  // their observations go with them
    std::snprintf(head + std::strlen(head), sizeof head - std::strlen(head),
                  "; with %lld point%s under --min-triangulation-angle",
                  static_cast<long long>(round.points_small_angle),
                  round.points_small_angle == 1 ? "" : "s");
  }
  std::strcat(head, ")");
  const std::string stop = "; nothing was written. ";
  if (share > guard.max_share) {
    char limit[80];
    std::snprintf(limit, sizeof limit, ", more than --reject-max-share %g: ", guard.max_share);
    throw RejectionStopped(head + std::string(limit) + LikelyCause(before) + stop +
                           "Raise --reject-max-share (1: no guard) to drop them anyway, or "
                           "--reject-outliers");
  }
  const int least = MinPoseObservations(side.model);
  const std::vector<int64_t> left = Undetermined(poses, side, least);
  if (left.empty()) return;
  const char* pose = side.has_rigs() ? "frame" : "image";
  const int64_t f = left.front();
  const int64_t named = poses.id.empty() ? f : poses.id[f];
  const int64_t after = f < static_cast<int64_t>(poses.after.size()) ? poses.after[f] : 0;
  throw RejectionStopped(
      std::string(head) + " and leave " + std::to_string(left.size()) + " " + pose +
      (left.size() == 1 ? "" : "s") + " with fewer than the " + std::to_string(least) +
      " observations that determine a pose (0-based " + pose + " " + std::to_string(named) + ": " +
      std::to_string(after) + " of " + std::to_string(poses.before[f]) + "): " +
      LikelyCause(before) + stop + "Raise --reject-outliers, or --reject-max-share to 1 (no guard)");
}

}  // namespace dba
