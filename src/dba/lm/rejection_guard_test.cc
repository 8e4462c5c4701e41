// The guard of --reject-outliers: which rounds stop the run and what they
// say; each pose's observations counted by image, or by frame with rigs.
#include "dba/lm/rejection_guard.h"

#include <gtest/gtest.h>

#include <string>

#include "dba/testing/synthetic_bal.h"
#include "dba/testing/synthetic_rig.h"

namespace dba {
namespace {

// The message of the round's stop, or "" when it passes.
std::string Stop(const RejectionGuard& guard, const RejectionRound& round,
                 const PoseObservations& poses, const Problem& side,
                 const SolveBeforeRound& before = {}) {
  try {
    CheckRejectionRound(guard, 3.0, 2, round, poses, side, before);
  } catch (const RejectionStopped& e) {
    return e.what();
  }
  return "";
}

RejectionRound Dropping(int64_t dropped, int64_t left) {
  RejectionRound r;
  r.observations_dropped = dropped;
  r.observations_left = left;
  return r;
}

// Four BAL cameras (9 unknowns each: 5 observations determine one).
Problem FourBalCameras() {
  Problem side;
  side.model = CameraModel::kBal;
  side.cameras.assign(4 * kBalCameraSize, 0.0);
  return side;
}

TEST(RejectionGuard, ARoundPastTheShareStopsSayingWhatToRaise) {
  const Problem side = FourBalCameras();
  const PoseObservations poses{{40, 40, 40, 40}, {40, 40, 40, 40}};
  EXPECT_EQ(Stop({0.25}, Dropping(25, 75), poses, side), "");  // at the share: goes on
  EXPECT_EQ(Stop({0.25}, Dropping(26, 74), poses, side),
            "outlier rejection round 2 (|r| > 3 px) would drop 26 of 100 observations (26.0%), "
            "more than --reject-max-share 0.25: the solve before it did not settle on the "
            "inliers, the threshold is below the noise, or that many are mismatches; nothing "
            "was written. Raise --reject-max-share (1: no guard) to drop them anyway, or "
            "--reject-outliers");
  const std::string squared =
      Stop({0.25}, Dropping(90, 10), poses, side, {TerminationReason::kMaxIterations, true});
  EXPECT_NE(squared.find("(90.0%), more than --reject-max-share 0.25: the solve before it had "
                         "the squared loss, which mismatches drag, and stopped at "
                         "--max-iterations unconverged"),
            std::string::npos)
      << squared;
  EXPECT_EQ(Stop({0.5}, Dropping(30, 70), poses, side), "");
  EXPECT_EQ(Stop({1.0}, Dropping(100, 0), poses, side), "");  // 1: no guard
}

TEST(RejectionGuard, APoseLeftWithTooFewObservationsStops) {
  Problem side = FourBalCameras();
  // Image 1 goes from 10 to 4 (5 determine a BAL camera); image 2 had 4
  // already; image 3 keeps exactly 5.
  const PoseObservations poses{{10, 10, 4, 9}, {10, 4, 4, 5}};
  EXPECT_EQ(Stop({0.25}, Dropping(10, 23), poses, side),
            "outlier rejection round 2 (|r| > 3 px) would drop 10 of 33 observations (30.3%), "
            "more than --reject-max-share 0.25: the solve before it did not settle on the "
            "inliers, the threshold is below the noise, or that many are mismatches; nothing "
            "was written. Raise --reject-max-share (1: no guard) to drop them anyway, or "
            "--reject-outliers");
  EXPECT_EQ(Stop({0.5}, Dropping(10, 23), poses, side),
            "outlier rejection round 2 (|r| > 3 px) would drop 10 of 33 observations (30.3%) "
            "and leave 1 image with fewer than the 5 observations that determine a pose "
            "(0-based image 1: 4 of 10): the solve before it did not settle on the inliers, the "
            "threshold is below the noise, or that many are mismatches; nothing was written. "
            "Raise --reject-outliers, or --reject-max-share to 1 (no guard)");
  EXPECT_EQ(Stop({1.0}, Dropping(10, 23), poses, side), "");
  // A fixed image has no unknowns to determine.
  side.fixed_cameras = {0, 1, 0, 0};
  EXPECT_EQ(Stop({0.5}, Dropping(10, 23), poses, side), "");
}

TEST(RejectionGuard, APoseOfSixUnknownsNeedsThree) {
  EXPECT_EQ(MinPoseObservations(CameraModel::kBal), 5);
  EXPECT_EQ(MinPoseObservations(CameraModel::kPhoto), 3);
  testing::SyntheticRigOptions o;
  o.frames = 3;
  o.sensors = 2;
  const Problem rig = testing::MakeSyntheticRig(o).problem;
  ASSERT_TRUE(rig.has_rigs());
  const PoseObservations poses{{8, 8, 8}, {8, 2, 3}};
  const std::string stop = Stop({0.9}, Dropping(11, 13), poses, rig);
  EXPECT_NE(stop.find("leave 1 frame with fewer than the 3 observations that determine a pose "
                      "(0-based frame 1: 2 of 8)"),
            std::string::npos)
      << stop;
}

TEST(RejectionGuard, ObservationsCountByImageOrFrame) {
  testing::SyntheticBalOptions b;
  b.num_cameras = 5;
  const Problem bal = testing::MakeSyntheticBal(b).problem;
  std::vector<int64_t> counts(bal.num_images(), 0), expected(bal.num_images(), 0);
  for (int32_t c : bal.obs_camera) ++expected[c];
  CountPoseObservations(bal, {}, &counts);
  EXPECT_EQ(counts, expected);
  // Mapped: each image counted at pose 4 - i (the counts grow to fit).
  std::vector<int64_t> mapped;
  const std::vector<int32_t> reversed = {4, 3, 2, 1, 0};
  CountPoseObservations(bal, reversed, &mapped);
  ASSERT_EQ(mapped.size(), 5u);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(mapped[4 - i], expected[i]);

  testing::SyntheticRigOptions r;
  r.frames = 4;
  r.sensors = 3;
  const Problem rig = testing::MakeSyntheticRig(r).problem;
  std::vector<int64_t> frames(rig.num_frames(), 0), by_frame(rig.num_frames(), 0);
  for (int32_t i : rig.obs_camera) ++by_frame[rig.image_frame[i]];
  CountPoseObservations(rig, {}, &frames);
  EXPECT_EQ(frames, by_frame);
}

}  // namespace
}  // namespace dba
