// The guard of --reject-outliers: a round is a test of the solve before it,
// and a round that would throw away what a settled solve keeps stops the run
// (the caller writes nothing) instead of solving on what is left. Two rules:
//
// - The share. Mismatches cost a round their own share and about 0.5% more
//   (the inliers past τ, the points left with one observation): 10% of
//   them 10.5%, 20% 20.5%, 30% 30.4% on generated surveys. A round past
//   max_share (0.25 by default) says the solve before it did not settle on
//   the inliers: it stopped at the iteration limit, or a squared loss was
//   dragged by the mismatches (1-10% uniform ones: 96-99.8% of the
//   observations), or τ is below the noise (bench/README.md, "Rejection
//   that starts robust").
// - The poses. A free pose (an image; with rigs a frame, whose images share
//   it) that had the observations that determine it, 2 equations each for
//   its unknowns (3 for a pose's 6, 5 for a BAL camera's 9), and would be
//   left with fewer: it would end where the solve leaves it, undetermined,
//   and no later round could test its observations.
//
// Thread safety: pure functions.
#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "dba/lm/levenberg_marquardt.h"
#include "dba/lm/outlier_rejection.h"
#include "dba/problem/problem.h"

namespace dba {

struct RejectionGuard {
  double max_share = 0.25;  // of the observations a round starts with; 1: no guard
};

// Per pose (an image, or with rigs a frame), its observations before and
// after a round, in the problem's numbering.
struct PoseObservations {
  std::vector<int64_t> before, after;
  // The number each counted pose had as the side was given it (a walked
  // side renumbers its images); empty: its index.
  std::vector<int64_t> id;
};

// Adds each observation of `problem` to its pose's count: counts[pose[f]]
// for the problem's frame f (pose empty: f itself). counts is grown to fit.
void CountPoseObservations(const Problem& problem, std::span<const int32_t> pose,
                           std::vector<int64_t>* counts);

// The observations that determine a pose of `model`: its unknowns / 2.
int MinPoseObservations(CameraModel model);

// What a stopped round says; the caller writes nothing.
class RejectionStopped : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The solve a round follows: why it ended, and whether its loss was squared.
struct SolveBeforeRound {
  TerminationReason termination = TerminationReason::kFunctionTolerance;
  bool squared = false;
};

// Throws RejectionStopped when round `r` (1-based), drawn at τ after
// `before`, breaks the guard: the share it would drop and what to raise, or
// the poses it would leave undetermined. `side`: the camera side (its
// model, rigs and fixed images).
void CheckRejectionRound(const RejectionGuard& guard, double max_error_px, int r,
                         const RejectionRound& round, const PoseObservations& poses,
                         const Problem& side, const SolveBeforeRound& before);

}  // namespace dba
