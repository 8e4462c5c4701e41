// Outlier rejection on a rank's share; see share_outliers.h.
#include "dba/cluster/share_outliers.h"

namespace dba {

RejectionRound DropShareOutliers(const RejectionCriteria& criteria, int num_threads,
                                 RankShare* share, ShareRejection* state,
                                 PoseObservations* poses) {
  if (!state->started) {
    state->started = true;
    state->loaded_point = share->global_point;
    state->loaded_offsets = share->problem.point_offsets;
    state->original = OriginalIndices::Identity(share->problem);
  }
  if (poses != nullptr) CountPoseObservations(share->problem, share->CameraRowIds(), &poses->before);
  const RejectionRound round =
      DropOutliers(criteria, num_threads, &share->problem, &state->original);
  if (poses != nullptr) CountPoseObservations(share->problem, share->CameraRowIds(), &poses->after);
  share->global_point.resize(state->original.point.size());
  for (size_t k = 0; k < state->original.point.size(); ++k) {
    share->global_point[k] = state->loaded_point[state->original.point[k]];
  }
  return round;
}

ShareLeft LeftOfShare(const RankShare& share, const ShareRejection& state) {
  ShareLeft left;
  if (!state.started) {  // nothing dropped: all of it
    left.point = share.global_point;
    left.count.resize(left.point.size());
    for (size_t k = 0; k < left.point.size(); ++k) {
      left.count[k] = share.problem.point_offsets[k + 1] - share.problem.point_offsets[k];
    }
    left.point_kept.assign(left.point.size(), 1);
    left.observation_kept.assign(share.problem.num_observations(), 1);
    return left;
  }
  left.point = state.loaded_point;
  left.count.resize(left.point.size());
  for (size_t k = 0; k < left.point.size(); ++k) {
    left.count[k] = state.loaded_offsets[k + 1] - state.loaded_offsets[k];
  }
  left.point_kept.assign(left.point.size(), 0);
  left.observation_kept.assign(state.loaded_offsets.back(), 0);
  for (int64_t k : state.original.point) left.point_kept[k] = 1;
  for (int64_t o : state.original.observation) left.observation_kept[o] = 1;
  return left;
}

KeptObservations MergeLeft(const std::vector<ShareLeft>& shares, int64_t num_points) {
  std::vector<int64_t> offsets(num_points + 1, 0);
  for (const ShareLeft& s : shares) {
    for (size_t k = 0; k < s.point.size(); ++k) offsets[s.point[k] + 1] = s.count[k];
  }
  for (int64_t k = 0; k < num_points; ++k) offsets[k + 1] += offsets[k];
  KeptObservations kept;
  kept.point.assign(num_points, 0);
  kept.observation.assign(offsets.back(), 0);
  for (const ShareLeft& s : shares) {
    int64_t o = 0;  // in the share's loaded observations
    for (size_t k = 0; k < s.point.size(); ++k) {
      kept.point[s.point[k]] = s.point_kept[k];
      for (int64_t j = 0; j < s.count[k]; ++j, ++o) {
        kept.observation[offsets[s.point[k]] + j] = s.observation_kept[o];
      }
    }
  }
  return kept;
}

}  // namespace dba
