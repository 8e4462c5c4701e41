// Outlier rejection on rank shares: the shares together drop what one
// process drops from the whole problem, over two rounds, for any split, and
// count each pose's observations before and after as one process does
// (the guard's figures); the main rank's merge of what is left gives back
// one process's problem.
#include "dba/cluster/share_outliers.h"

#include <gtest/gtest.h>

#include "dba/cluster/partition.h"
#include "dba/testing/synthetic_bal.h"
#include "dba/testing/synthetic_rig.h"

namespace dba {
namespace {

TEST(ShareOutliers, SharesDropWhatOneProcessDrops) {
  testing::SyntheticBalOptions o;
  o.num_cameras = 8;
  o.num_points = 120;
  o.max_track = 5;
  o.pixel_noise = 0.5;
  Problem loaded = testing::MakeSyntheticBal(o).problem;
  // Every fifth observation moved by 30 px (some points then keep one).
  for (int64_t a = 0; a < loaded.num_observations(); a += 5) loaded.obs_pixel[2 * a + 1] += 30.0;
  // Two rounds with a lower bound the second time; the angle rule on.
  const RejectionCriteria first{10.0, 1.0}, second{1.0, 1.0};

  Problem whole = loaded;
  OriginalIndices original = OriginalIndices::Identity(whole);
  const int64_t images = loaded.num_images();
  std::vector<int64_t> whole_counts[3];  // before round 1, after it, after round 2
  for (auto& c : whole_counts) c.assign(images, 0);
  CountPoseObservations(whole, {}, &whole_counts[0]);
  const RejectionRound w1 = DropOutliers(first, 1, &whole, &original);
  CountPoseObservations(whole, {}, &whole_counts[1]);
  const RejectionRound w2 = DropOutliers(second, 1, &whole, &original);
  CountPoseObservations(whole, {}, &whole_counts[2]);
  ASSERT_GT(w1.observations_dropped, 0);
  ASSERT_GT(w2.observations_dropped, 0);

  for (PartitionScheme scheme : {PartitionScheme::kEqual, PartitionScheme::kCameraLocality}) {
    const auto group = PartitionPoints(loaded, 3, scheme);
    std::vector<RankShare> shares;
    std::vector<ShareRejection> states(3);
    for (int g = 0; g < 3; ++g) shares.push_back(ExtractShare(loaded, group, g));
    RejectionRound s1, s2;
    PoseObservations p1, p2;  // summed over the shares
    for (int g = 0; g < 3; ++g) {
      const RejectionRound a = DropShareOutliers(first, 2, &shares[g], &states[g], &p1);
      const RejectionRound b = DropShareOutliers(second, 2, &shares[g], &states[g], &p2);
      s1.observations_dropped += a.observations_dropped;
      s1.points_dropped += a.points_dropped;
      s2.observations_dropped += b.observations_dropped;
      s2.points_dropped += b.points_dropped;
      s2.points_left += b.points_left;
      s2.observations_left += b.observations_left;
      // The share's global ids follow its points.
      for (int64_t k = 0; k < shares[g].problem.num_points(); ++k) {
        EXPECT_EQ(shares[g].problem.points[3 * k], loaded.points[3 * shares[g].global_point[k]]);
      }
    }
    EXPECT_EQ(s1.observations_dropped, w1.observations_dropped);
    EXPECT_EQ(s1.points_dropped, w1.points_dropped);
    EXPECT_EQ(s2.observations_dropped, w2.observations_dropped);
    EXPECT_EQ(s2.points_dropped, w2.points_dropped);
    EXPECT_EQ(s2.points_left, whole.num_points());
    EXPECT_EQ(s2.observations_left, whole.num_observations());
    for (auto* c : {&p1.before, &p1.after, &p2.before, &p2.after}) c->resize(images, 0);
    EXPECT_EQ(p1.before, whole_counts[0]);
    EXPECT_EQ(p1.after, whole_counts[1]);
    EXPECT_EQ(p2.before, whole_counts[1]);
    EXPECT_EQ(p2.after, whole_counts[2]);

    std::vector<ShareLeft> left;
    for (int g = 0; g < 3; ++g) left.push_back(LeftOfShare(shares[g], states[g]));
    const KeptObservations kept = MergeLeft(left, loaded.num_points());
    std::vector<uint8_t> point(loaded.num_points(), 0), observation(loaded.num_observations(), 0);
    for (int64_t k : original.point) point[k] = 1;
    for (int64_t a : original.observation) observation[a] = 1;
    EXPECT_EQ(kept.point, point);
    EXPECT_EQ(kept.observation, observation);

    Problem reduced = loaded;
    KeepOnly(kept, &reduced);
    EXPECT_EQ(reduced.point_offsets, whole.point_offsets);
    EXPECT_EQ(reduced.obs_camera, whole.obs_camera);
    EXPECT_EQ(reduced.obs_pixel, whole.obs_pixel);
    EXPECT_EQ(reduced.points, whole.points);
  }
}

// With rigs a pose is a frame: the shares' counts, by their global frames,
// sum to the whole problem's.
TEST(ShareOutliers, RigSharesCountEachFrameAsTheWhole) {
  testing::SyntheticRigOptions o;
  o.frames = 6;
  o.sensors = 3;
  const Problem loaded = testing::MakeSyntheticRig(o).problem;
  std::vector<int64_t> whole(loaded.num_frames(), 0);
  CountPoseObservations(loaded, {}, &whole);
  const auto group = PartitionPoints(loaded, 3, PartitionScheme::kCameraLocality);
  PoseObservations poses;
  for (int g = 0; g < 3; ++g) {
    RankShare share = ExtractShare(loaded, group, g);
    ShareRejection state;
    DropShareOutliers({1e6, 0.0}, 1, &share, &state, &poses);  // drops nothing
  }
  poses.before.resize(whole.size(), 0);
  poses.after.resize(whole.size(), 0);
  EXPECT_EQ(poses.before, whole);
  EXPECT_EQ(poses.after, whole);
}

TEST(ShareOutliers, AShareNeverRejectedIsLeftWhole) {
  testing::SyntheticBalOptions o;
  const Problem loaded = testing::MakeSyntheticBal(o).problem;
  const auto group = PartitionPoints(loaded, 2, PartitionScheme::kEqual);
  std::vector<ShareLeft> left;
  for (int g = 0; g < 2; ++g) left.push_back(LeftOfShare(ExtractShare(loaded, group, g), {}));
  const KeptObservations kept = MergeLeft(left, loaded.num_points());
  EXPECT_EQ(kept.point, std::vector<uint8_t>(loaded.num_points(), 1));
  EXPECT_EQ(kept.observation, std::vector<uint8_t>(loaded.num_observations(), 1));
}

}  // namespace
}  // namespace dba
