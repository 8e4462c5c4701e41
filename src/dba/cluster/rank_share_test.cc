// A rank's share: the points of its group with their observations, in
// global order, and only the cameras (and intrinsic groups) they touch,
// renumbered, with the global ids kept.
#include "dba/cluster/rank_share.h"

#include <gtest/gtest.h>

#include <set>

#include "dba/camera/rig_pose.h"
#include "dba/problem/point_order.h"
#include "dba/rcs/unknown_layout.h"
#include "dba/testing/synthetic_photo.h"
#include "dba/testing/synthetic_rig.h"
#include "dba/testing/scattered_survey.h"

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
    if (k > 0) {
      EXPECT_GT(g, share.global_point[k - 1]);  // global order
    }
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
    if (i > 0) {
      EXPECT_GT(share.global_camera[i], share.global_camera[i - 1]);
    }
    for (int d = 0; d < p.camera_size(); ++d) {
      EXPECT_EQ(p.camera(i)[d], full.camera(share.global_camera[i])[d]);
    }
    const int32_t g = p.camera_intrinsics[i];
    EXPECT_EQ(share.global_intrinsics[g], full.camera_intrinsics[share.global_camera[i]]);
  }
}

// Rigs: a share keeps the frames of its images and the sensors of its
// groups, so its images compose to the global poses, and its camera rows
// stand for global frames.
TEST(RankShare, KeepsTheFramesAndSensorsOfItsImages) {
  testing::SyntheticRigOptions o;
  o.frames = 8;
  o.sensors = 3;
  o.missing = true;
  const Problem full = testing::MakeSyntheticRig(o).problem;
  std::vector<int32_t> group(full.num_points());
  // Points seen in frame 0 in one share: the other may lack some frames.
  for (int64_t k = 0; k < full.num_points(); ++k) group[k] = full.image_frame[full.obs_camera[full.point_offsets[k]]] == 0;
  for (int32_t g = 0; g < 2; ++g) {
    const RankShare share = ExtractShare(full, group, g);
    Problem local = share.problem;
    ASSERT_TRUE(local.has_rigs()) << "share " << g;
    ASSERT_GT(local.num_points(), 0);
    ASSERT_EQ(static_cast<int64_t>(share.global_frame.size()), local.num_frames());
    for (int64_t f = 0; f < local.num_frames(); ++f) {
      for (int k = 0; k < 6; ++k) {
        EXPECT_EQ(local.cameras[local.frame_offset(f) + k],
                  full.cameras[full.frame_offset(share.global_frame[f]) + k]);
      }
    }
    ComposeRigImages(&local);
    for (int64_t i = 0; i < local.num_images(); ++i) {
      EXPECT_EQ(share.global_frame[local.image_frame[i]], full.image_frame[share.global_camera[i]]);
      for (int k = 0; k < 6; ++k) EXPECT_EQ(local.camera(i)[k], full.camera(share.global_camera[i])[k]);
    }
    const UnknownLayout global(full), layout(local);
    const std::vector<int32_t> rows =
        global.RowsOfEntities(layout.RowEntities(share.CameraRowIds(), share.global_intrinsics));
    for (int64_t i = 0; i < local.num_images(); ++i) {
      EXPECT_EQ(rows[layout.camera_row(i)], global.camera_row(share.global_camera[i]));
    }
  }
}

// A share of a survey whose points come in a random order is walked: each
// point keeps its global id, coordinates and observations; the walk is the
// one PointWalk takes, its cameras are numbered as the walk first sees them,
// and a walked share is local (walked again: as is).
TEST(RankShare, AScatteredShareIsWalkedWithItsGlobalIds) {
  const Problem full = testing::MakeScatteredSurvey("walk_share.dba", 40, 120, 3, 2).scattered;
  const std::vector<int32_t> group(full.num_points(), 0);
  RankShare share = ExtractShare(full, group, 0);
  const std::vector<int64_t> walk = PointWalk(share.problem);
  ASSERT_FALSE(walk.empty());
  WalkShare(&share);
  ASSERT_EQ(share.problem.num_points(), full.num_points());
  for (int64_t k = 0; k < share.problem.num_points(); ++k) {
    const int64_t g = share.global_point[k];
    EXPECT_EQ(g, walk[k]);
    for (int d = 0; d < 3; ++d) EXPECT_EQ(share.problem.point(k)[d], full.point(g)[d]);
    const int64_t n = share.problem.point_offsets[k + 1] - share.problem.point_offsets[k];
    ASSERT_EQ(n, full.point_offsets[g + 1] - full.point_offsets[g]);
    for (int64_t j = 0; j < n; ++j) {
      const int64_t a = share.problem.point_offsets[k] + j, b = full.point_offsets[g] + j;
      EXPECT_EQ(share.global_camera[share.problem.obs_camera[a]], full.obs_camera[b]);
      EXPECT_EQ(share.problem.obs_pixel[2 * a], full.obs_pixel[2 * b]);
    }
  }
  // Its cameras numbered as the walk first sees them, each with its own
  // parameters.
  EXPECT_EQ(CamerasInPointOrder(share.problem), [&] {
    std::vector<int64_t> identity(share.problem.num_images());
    for (size_t i = 0; i < identity.size(); ++i) identity[i] = static_cast<int64_t>(i);
    return identity;
  }());
  for (int64_t i = 0; i < share.problem.num_images(); ++i) {
    for (int d = 0; d < share.problem.camera_size(); ++d) {
      EXPECT_EQ(share.problem.camera(i)[d], full.camera(share.global_camera[i])[d]);
    }
  }
  EXPECT_TRUE(PointWalk(share.problem).empty());
  const std::vector<int64_t> before = share.global_point;
  WalkShare(&share);
  EXPECT_EQ(share.global_point, before);
}

}  // namespace
}  // namespace dba
