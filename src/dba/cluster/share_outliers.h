// --reject-outliers on the ranks (lm/outlier_rejection.h): each rank drops
// from its share what one process would drop from the whole problem. Each
// rule looks at one observation (its reprojection error) or one point (its
// observations left, its triangulation angle), so how the points are split
// changes nothing. A share remembers what it was loaded with, so that at the
// end the main rank learns which of the loaded observations are left.
//
// Thread safety: one caller per share.
#pragma once

#include <cstdint>
#include <vector>

#include "dba/cluster/rank_share.h"
#include "dba/lm/outlier_rejection.h"
#include "dba/lm/rejection_guard.h"

namespace dba {

// A share's state across rejection rounds.
struct ShareRejection {
  bool started = false;
  std::vector<int64_t> loaded_point;   // global ids of the share's loaded points
  std::vector<int64_t> loaded_offsets; // their observations (point_offsets)
  OriginalIndices original;            // current -> loaded, in the share
};

// One round on the share; its global_point follows the points left. With
// `poses`, each global pose's observations in the share before and after
// the round are added to it (lm/rejection_guard.h).
RejectionRound DropShareOutliers(const RejectionCriteria& criteria, int num_threads,
                                 RankShare* share, ShareRejection* state,
                                 PoseObservations* poses = nullptr);

// What is left of a share, in its loaded order: each loaded point's global id
// and number of observations, a flag per loaded point and per loaded
// observation.
struct ShareLeft {
  std::vector<int64_t> point;
  std::vector<int64_t> count;
  std::vector<uint8_t> point_kept;
  std::vector<uint8_t> observation_kept;
};
ShareLeft LeftOfShare(const RankShare& share, const ShareRejection& state);

// The main rank: every share's ShareLeft into flags over the loaded problem
// (`num_points` points; a point's observations are contiguous and in share
// order in the loaded problem, as in every share).
KeptObservations MergeLeft(const std::vector<ShareLeft>& shares, int64_t num_points);

}  // namespace dba
