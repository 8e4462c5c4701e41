// A rank's share: the points of its group with their observations, in
// global order, and only the cameras (and intrinsic groups) they touch,
// renumbered, with the global ids kept.
#include "dba/cluster/rank_share.h"

#include <gtest/gtest.h>

#include <set>

#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

TEST(RankShare, HoldsItsPointsAndTheCamerasTheyTouch) {
  testing::SyntheticPhotoOptions o;
  o.geometry.num_cameras = 8;
  o.geometry.num_points = 60;
  o.num_groups = 3;
  const Problem full = testing::MakeSyntheticPhoto(o).problem;
  // Points by the cameras that see them: each share sees some cameras only.
  std::vector<int32_t> group(full.num_points());
  for (int64_t k = 0; k < full.num_points(); ++k) {
    group[k] = 1;
    for (int64_t o = full.point_offsets[k]; o < full.point_offsets[k + 1]; ++o) {
      if (full.obs_camera[o] == 0 || full.obs_camera[o] == 5) group[k] = 0;
    }
  }
  const RankShare share = ExtractShare(full, group, 1);
  const Problem& p = share.problem;
  ASSERT_GT(p.num_points(), 0);
  std::set<int32_t> touched;
  for (int64_t k = 0; k < p.num_points(); ++k) {
    const int64_t g = share.global_point[k];
    EXPECT_EQ(group[g], 1);
    if (k > 0) EXPECT_GT(g, share.global_point[k - 1]);  // global order
    for (int d = 0; d < 3; ++d) EXPECT_EQ(p.points[3 * k + d], full.points[3 * g + d]);
    ASSERT_EQ(p.point_offsets[k + 1] - p.point_offsets[k],
              full.point_offsets[g + 1] - full.point_offsets[g]);
    for (int64_t j = 0; j < p.point_offsets[k + 1] - p.point_offsets[k]; ++j) {
      const int64_t o_local = p.point_offsets[k] + j, o_full = full.point_offsets[g] + j;
      const int32_t camera = share.global_camera[p.obs_camera[o_local]];
      EXPECT_EQ(camera, full.obs_camera[o_full]);
      EXPECT_EQ(p.obs_pixel[2 * o_local], full.obs_pixel[2 * o_full]);
      touched.insert(camera);
    }
  }
  // Only the cameras its observations touch, renumbered in increasing order,
  // with their parameters and their groups' (global ids kept).
  EXPECT_EQ(share.global_camera.size(), touched.size());
  EXPECT_LT(touched.size(), static_cast<size_t>(full.num_images()));
  for (size_t i = 0; i < share.global_camera.size(); ++i) {
    if (i > 0) EXPECT_GT(share.global_camera[i], share.global_camera[i - 1]);
    for (int d = 0; d < p.camera_size(); ++d) {
      EXPECT_EQ(p.camera(i)[d], full.camera(share.global_camera[i])[d]);
    }
    const int32_t g = p.camera_intrinsics[i];
    EXPECT_EQ(share.global_intrinsics[g], full.camera_intrinsics[share.global_camera[i]]);
  }
}

}  // namespace
}  // namespace dba
