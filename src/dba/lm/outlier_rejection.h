// Outlier rejection between solves (COLMAP's global BA filter): drop every
// observation whose reprojection error |r| exceeds a threshold, then every
// point left with fewer than two observations or whose rays meet at too
// small an angle (COLMAP's FilterPoints3DWithSmallTriangulationAngle: such a
// point's depth is not determined, and a mismatch along its epipolar line
// can put it anywhere on the rays), and keep track of where the remaining
// observations and points came from. Control points (points with a prior)
// lose outlying observations but are never dropped themselves.
//
// Thread safety: one caller per problem.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "dba/problem/problem.h"
#include "dba/rcs/robust_loss.h"

namespace dba {

struct RejectionCriteria {
  double max_error_px = 4.0;
  // A point is dropped when the largest angle between the rays of two of its
  // kept observations (camera centre to point) is below this; 0: off.
  // COLMAP's default, 1.5 degrees.
  double min_triangulation_angle_deg = 1.5;
};

// The first solve's loss under rejection at τ = max_error_px when no loss
// is given: Cauchy, ρ(s) = a² log(1 + s/a²), at a = 2τ. A squared first
// solve is dragged by the mismatches and its round then drops the inliers
// (3% uniform mismatches: 98.7% of them); Cauchy gives a mismatch 50 px out
// a weight under 0.04 at τ = 3 px, and at 2τ rather than τ it drops fewer
// inliers in the round after it and lands the cameras closer (bench/README.md,
// "Rejection that starts robust").
RobustLoss RejectionStartLoss(double max_error_px);

struct RejectionRound {
  int64_t observations_dropped = 0;
  int64_t points_dropped = 0;
  int64_t points_small_angle = 0;  // of points_dropped: for the angle alone
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

// What is left after outlier rejection, as a flag per observation and per
// point of the problem as loaded.
struct KeptObservations {
  std::vector<uint8_t> observation;
  std::vector<uint8_t> point;
};

// Keeps only what `kept` flags in `problem` (the problem as loaded; a point
// is kept with the observations flagged among its own).
void KeepOnly(const KeptObservations& kept, Problem* problem);

// The rounds of --reject-outliers after the first solve (COLMAP's global BA
// filter): `drop` one round, then `solve_again`, until a round drops nothing
// or fewer than 0.05% of the observations it started with, or after 5
// rounds. `on_round` hears of each round as it ends (1-based). `done`: the
// rounds a resumed solve had done (io/checkpoint.h); it resumes with the
// solve after the last of them, then goes on as the uninterrupted one would.
std::vector<RejectionRound> RunRejectionRounds(
    const std::function<RejectionRound()>& drop, const std::function<void()>& solve_again,
    const std::function<void(int, const RejectionRound&)>& on_round,
    std::vector<RejectionRound> done = {});

// The flags of what `original` holds, over `observations` and `points` as
// loaded; and the indices back from such flags.
KeptObservations KeptFlags(const OriginalIndices& original, int64_t observations, int64_t points);
OriginalIndices IndicesOf(const KeptObservations& kept);

// Drops from `problem` the observations with |r| > max_error_px at its
// current parameters, then the points with fewer than 2 observations left or
// a triangulation angle below the minimum, and updates `original` to match.
// The camera side is unchanged.
RejectionRound DropOutliers(const RejectionCriteria& criteria, int num_threads, Problem* problem,
                            OriginalIndices* original);

// The camera centres -Rᵀ t of `problem`'s images, 3 per image.
std::vector<double> CameraCentres(const Problem& problem);

// The largest angle (radians) between two rays from camera centres to point
// k, over the point's observations o with keep[o] set.
double MaxTriangulationAngle(const Problem& problem, const std::vector<double>& centres, int64_t k,
                             const uint8_t* keep);

}  // namespace dba
