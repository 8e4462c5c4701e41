// Outlier rejection between solves (COLMAP's global BA filter): drop every
// observation whose reprojection error |r| exceeds a threshold, then every
// point left with fewer than two observations, and keep track of where the
// remaining observations and points came from.
//
// Thread safety: one caller per problem.
#pragma once

#include <cstdint>
#include <vector>

#include "dba/problem/problem.h"

namespace dba {

struct RejectionRound {
  int64_t observations_dropped = 0;
  int64_t points_dropped = 0;
  int64_t observations_left = 0;
  int64_t points_left = 0;
};

// Where the problem's observations and points stand in the problem as it was
// loaded.
struct OriginalIndices {
  std::vector<int64_t> observation;  // current observation -> loaded one
  std::vector<int64_t> point;        // current point -> loaded one
  // The identity for `problem`.
  static OriginalIndices Identity(const Problem& problem);
};

// Drops from `problem` the observations with |r| > max_error_px at its
// current parameters, then the points with fewer than 2 observations left,
// and updates `original` to match. The camera side is unchanged.
RejectionRound DropOutliers(double max_error_px, int num_threads, Problem* problem,
                            OriginalIndices* original);

}  // namespace dba
