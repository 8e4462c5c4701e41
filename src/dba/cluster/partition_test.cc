// Point partitions: every point in exactly one group, equal split sizes, and
// the camera-locality split keeps each group's camera set small.
#include "dba/cluster/partition.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "dba/cluster/rank_share.h"
#include "dba/io/checkpoint.h"
#include "dba/testing/synthetic_bal.h"

namespace dba {
namespace {

// A strip of cameras where each point is seen by 2-3 consecutive cameras.
Problem Strip(int cameras, int points_per_camera) {
  Problem p;
  p.cameras.assign(9 * cameras, 0.0);
  p.point_offsets.push_back(0);
  for (int c = 0; c + 2 < cameras; ++c) {
    for (int k = 0; k < points_per_camera; ++k) {
      const int track = 2 + (k % 2);
      for (int a = 0; a < track; ++a) {
        p.obs_camera.push_back(c + a);
        p.obs_pixel.insert(p.obs_pixel.end(), {0.0, 0.0});
      }
      p.points.insert(p.points.end(), {0.0, 0.0, 0.0});
      p.point_offsets.push_back(p.num_observations());
    }
  }
  return p;
}

TEST(Partition, EqualSplitHasEqualContiguousGroups) {
  const Problem p = Strip(20, 10);  // 180 points
  const auto group = PartitionPoints(p, 4, PartitionScheme::kEqual);
  ASSERT_EQ(static_cast<int64_t>(group.size()), p.num_points());
  EXPECT_TRUE(std::is_sorted(group.begin(), group.end()));
  for (int g = 0; g < 4; ++g) EXPECT_EQ(std::count(group.begin(), group.end(), g), 45);
}

TEST(Partition, CameraLocalityKeepsCameraSetsSmallAndBalanced) {
  const Problem p = Strip(40, 10);
  const int groups = 4;
  const auto group = PartitionPoints(p, groups, PartitionScheme::kCameraLocality);
  int64_t total_cameras = 0, total_obs = 0;
  for (int g = 0; g < groups; ++g) {
    const RankShare s = ExtractShare(p, group, g);
    total_cameras += static_cast<int64_t>(s.global_camera.size());
    total_obs += s.problem.num_observations();
    // About a quarter of the observations each.
    EXPECT_NEAR(s.problem.num_observations(), p.num_observations() / groups,
                0.15 * p.num_observations() / groups);
  }
  EXPECT_EQ(total_obs, p.num_observations());
  // Neighbouring groups share at most a couple of boundary cameras.
  EXPECT_LE(total_cameras, 40 + 2 * (groups - 1));
}

TEST(Partition, CameraGraphOrderIsAPermutation) {
  testing::SyntheticBalOptions o;
  o.num_cameras = 15;
  o.num_points = 60;
  const Problem p = testing::MakeSyntheticBal(o).problem;
  std::vector<int32_t> order = CameraGraphOrder(p);
  std::sort(order.begin(), order.end());
  for (int i = 0; i < 15; ++i) EXPECT_EQ(order[i], i);
}

TEST(Partition, ParsesSchemeNames) {
  EXPECT_EQ(ParsePartitionScheme("equal"), PartitionScheme::kEqual);
  EXPECT_EQ(ParsePartitionScheme("cameras"), PartitionScheme::kCameraLocality);
  EXPECT_THROW(ParsePartitionScheme("metis"), std::invalid_argument);
}

TEST(RankShare, RenumbersCamerasInGlobalOrderAndKeepsObservations) {
  testing::SyntheticBalOptions o;
  o.num_cameras = 9;
  o.num_points = 50;
  const Problem p = testing::MakeSyntheticBal(o).problem;
  const auto group = PartitionPoints(p, 3, PartitionScheme::kEqual);
  for (int g = 0; g < 3; ++g) {
    const RankShare s = ExtractShare(p, group, g);
    EXPECT_TRUE(std::is_sorted(s.global_camera.begin(), s.global_camera.end()));
    for (size_t i = 0; i < s.global_camera.size(); ++i) {
      for (int d = 0; d < 9; ++d) {
        EXPECT_EQ(s.problem.camera(i)[d], p.camera(s.global_camera[i])[d]);
      }
    }
    for (int64_t k = 0; k < s.problem.num_points(); ++k) {
      const int64_t gk = s.global_point[k];
      ASSERT_EQ(s.problem.point_offsets[k + 1] - s.problem.point_offsets[k],
                p.point_offsets[gk + 1] - p.point_offsets[gk]);
      for (int64_t a = 0; a < s.problem.point_offsets[k + 1] - s.problem.point_offsets[k]; ++a) {
        const int64_t lo = s.problem.point_offsets[k] + a, go = p.point_offsets[gk] + a;
        EXPECT_EQ(s.global_camera[s.problem.obs_camera[lo]], p.obs_camera[go]);
        EXPECT_EQ(s.problem.obs_pixel[2 * lo], p.obs_pixel[2 * go]);
      }
    }
  }
}

// A checkpoint's fingerprint of a problem spread over ranks (the sum of the
// shares' observation hashes, io/checkpoint.h) is the whole problem's, for
// any partition, and moves when one pixel does.
TEST(Partition, SharesSumToTheWholeProblemsFingerprint) {
  testing::SyntheticBalOptions options;
  options.num_cameras = 8;
  options.num_points = 200;
  const Problem full = testing::MakeSyntheticBal(options).problem;
  const uint64_t whole = ObservationsFingerprint(full, {}, {});
  for (PartitionScheme scheme : {PartitionScheme::kEqual, PartitionScheme::kCameraLocality}) {
    const auto group = PartitionPoints(full, 3, scheme);
    uint64_t sum = 0;
    for (int g = 0; g < 3; ++g) {
      const RankShare s = ExtractShare(full, group, g);
      sum += ObservationsFingerprint(s.problem, s.global_point, s.global_camera);
    }
    EXPECT_EQ(sum, whole);
    EXPECT_EQ(CombineFingerprints(CameraSideFingerprint(full, full.num_points()), sum),
              ProblemFingerprint(full));
  }
  Problem moved = full;
  moved.obs_pixel[17] += 0.5;
  EXPECT_NE(ObservationsFingerprint(moved, {}, {}), whole);
}

}  // namespace
}  // namespace dba
