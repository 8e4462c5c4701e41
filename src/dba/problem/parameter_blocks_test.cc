// The table of parameter blocks against CameraSide's own offsets, for BAL,
// photogrammetric and rig camera sides with held parameters and a lever
// arm; every parameter is in exactly one block, and the RCS's unknowns are
// the table's free parameters.
#include "dba/problem/parameter_blocks.h"

#include <gtest/gtest.h>

#include "dba/rcs/unknown_layout.h"

namespace dba {
namespace {

// The blocks follow each other with no gap and cover the parameter vector.
void ExpectContiguous(const ParameterBlocks& t) {
  int64_t next = 0;
  for (const ParameterBlock& b : t.blocks()) {
    EXPECT_EQ(b.offset, next);
    next += b.size;
  }
  EXPECT_EQ(next, t.num_parameters());
}

TEST(ParameterBlocks, BalImagesHeldOrFree) {
  CameraSide side;
  side.cameras.assign(3 * kBalCameraSize, 0.0);
  side.fixed_cameras = {0, 1, 0};
  const ParameterBlocks t(side);
  ASSERT_EQ(t.blocks().size(), 3u);
  ExpectContiguous(t);
  EXPECT_EQ(t[1].kind, BlockKind::kBalCamera);
  EXPECT_EQ(t[1].free, 0u);
  EXPECT_EQ(t[2].free, 0x1FFu);
  EXPECT_EQ(t[2].step, BlockStep::kPose);
  EXPECT_EQ(t.num_unknowns(), 18);
  EXPECT_EQ(t.lever_arm_block(), -1);
  EXPECT_EQ(UnknownLayout(side).num_unknowns(), t.num_unknowns());
}

TEST(ParameterBlocks, PhotoPosesAndGroupsWithHeldIntrinsicsAndALeverArm) {
  CameraSide side;
  side.model = CameraModel::kPhoto;
  side.camera_intrinsics = {0, 1, 1};
  side.cameras.assign(3 * kPhotoPoseSize + 2 * kPhotoIntrinsicsSize, 0.0);
  side.fixed_intrinsics = {0, kIntrinsicCx | kIntrinsicCy};
  const ParameterBlocks t(side, true);
  ASSERT_EQ(t.blocks().size(), 6u);
  ExpectContiguous(t);
  EXPECT_EQ(t[t.group_block(1)].kind, BlockKind::kIntrinsics);
  EXPECT_EQ(t[t.group_block(1)].offset, side.intrinsics_offset(1));
  EXPECT_EQ(t[t.group_block(1)].free, uint32_t{kIntrinsicF | kIntrinsicK1 | kIntrinsicK2});
  EXPECT_EQ(t[t.lever_arm_block()].offset, static_cast<int64_t>(side.cameras.size()));
  EXPECT_EQ(t.num_parameters(), static_cast<int64_t>(side.cameras.size()) + 3);
  EXPECT_EQ(t.num_unknowns(BlockKind::kImagePose), 18);
  EXPECT_EQ(t.num_unknowns(BlockKind::kIntrinsics), 5 + 3);
  EXPECT_EQ(t.num_unknowns(BlockKind::kLeverArm), 3);
  const UnknownLayout layout(side, true);
  EXPECT_EQ(layout.num_unknowns(), t.num_unknowns());
  EXPECT_EQ(layout.param_offset(layout.lever_arm_row()), t[t.lever_arm_block()].offset);
}

// Four images on two frames of a two-sensor rig; image 2 held holds frame 1;
// sensor 0 the rig's origin, sensor 1 refined.
TEST(ParameterBlocks, RigFramesAndSensorsWithImagesComposed) {
  CameraSide side;
  side.model = CameraModel::kPhoto;
  side.camera_intrinsics = {0, 1, 0, 1};
  side.image_frame = {0, 0, 1, 1};
  side.sensor_kind = {kRigOrigin, kSensorRefined};
  side.cameras.assign(4 * kPhotoPoseSize + 2 * kPhotoIntrinsicsSize + 2 * 6 + 2 * 6, 0.0);
  side.fixed_cameras = {0, 0, 1, 0};
  side.fixed_intrinsics = {kAllIntrinsics, kAllIntrinsics};
  const ParameterBlocks t(side);
  ASSERT_EQ(t.blocks().size(), 4u + 2 + 2 + 2);
  ExpectContiguous(t);
  for (int64_t i = 0; i < 4; ++i) {
    EXPECT_EQ(t[t.image_block(i)].step, BlockStep::kComposed);
    EXPECT_EQ(t[t.image_block(i)].free, 0u);
  }
  EXPECT_EQ(t[t.frame_block(1)].offset, side.frame_offset(1));
  EXPECT_EQ(t[t.frame_block(0)].free, 0x3Fu);
  EXPECT_EQ(t[t.frame_block(1)].free, 0u);
  EXPECT_EQ(t[t.sensor_block(1)].offset, side.sensor_offset(1));
  EXPECT_EQ(t[t.sensor_block(0)].free, 0u);
  EXPECT_EQ(t[t.sensor_block(1)].scope, BlockScope::kGroup);
  EXPECT_EQ(t.num_unknowns(), 6 + 6);
  const UnknownLayout layout(side);
  EXPECT_EQ(layout.num_unknowns(), t.num_unknowns());
  EXPECT_EQ(layout.camera_row(2), -1);
  EXPECT_EQ(layout.intrinsics_row(0), -1);
  EXPECT_EQ(layout.block_size(layout.intrinsics_row(1)), 6);
}

}  // namespace
}  // namespace dba
