// The unknowns of the RCS: rows, sizes and offsets for each way of holding
// parameters fixed, x ⊞ δ, and the mapping of a share's rows to the
// problem's.
#include "dba/rcs/unknown_layout.h"

#include <gtest/gtest.h>

#include "dba/camera/pose_step.h"

namespace dba {
namespace {

Problem PhotoCameras(int images, int groups) {
  Problem p;
  p.model = CameraModel::kPhoto;
  for (int i = 0; i < images; ++i) p.camera_intrinsics.push_back(i % groups);
  p.cameras.resize(kPhotoPoseSize * images + kPhotoIntrinsicsSize * groups);
  for (size_t j = 0; j < p.cameras.size(); ++j) p.cameras[j] = static_cast<double>(j);
  return p;
}

TEST(UnknownLayout, BalCamerasAreNineWideRows) {
  Problem p;
  p.cameras.assign(9 * 4, 1.0);
  p.fixed_cameras = {0, 1, 0, 0};
  const UnknownLayout l(p);
  EXPECT_EQ(l.num_block_rows(), 3);
  EXPECT_EQ(l.num_unknowns(), 27);
  EXPECT_EQ(l.camera_row(0), 0);
  EXPECT_EQ(l.camera_row(1), -1);
  EXPECT_EQ(l.camera_row(3), 2);
  EXPECT_EQ(l.param_offset(2), 27);
  EXPECT_EQ(l.intrinsics_row(0), -1);
}

TEST(UnknownLayout, PhotoRowsPosesThenFreeIntrinsics) {
  Problem p = PhotoCameras(5, 3);
  p.fixed_cameras = {1, 0, 0, 0, 0};
  p.fixed_intrinsics = {0, kAllIntrinsics, kIntrinsicCx | kIntrinsicCy | kIntrinsicK1};
  const UnknownLayout l(p);
  ASSERT_EQ(l.num_block_rows(), 4 + 2);
  EXPECT_EQ(l.num_camera_rows(), 4);
  EXPECT_EQ(l.camera_row(0), -1);
  EXPECT_EQ(l.camera_row(1), 0);
  EXPECT_EQ(l.intrinsics_row(0), 4);
  EXPECT_EQ(l.intrinsics_row(1), -1);
  EXPECT_EQ(l.intrinsics_row(2), 5);
  EXPECT_EQ(l.block_size(4), 5);
  EXPECT_EQ(l.block_size(5), 2);
  EXPECT_EQ(l.num_unknowns(), 4 * 6 + 5 + 2);
  EXPECT_EQ(l.row_offset(5), 29);
  EXPECT_EQ(l.param_offset(5), 5 * 6 + 2 * 5);
  EXPECT_EQ(l.intrinsics_free_index(2)[0], 0);
  EXPECT_EQ(l.intrinsics_free_index(2)[1], 4);
}

TEST(UnknownLayout, PlusMovesOnlyFreeParameters) {
  Problem p = PhotoCameras(2, 2);
  p.fixed_cameras = {0, 1};
  p.fixed_intrinsics = {kIntrinsicF | kIntrinsicK1 | kIntrinsicK2,
                        kIntrinsicF | kIntrinsicCx | kIntrinsicCy | kIntrinsicK2};
  const UnknownLayout l(p);
  ASSERT_EQ(l.num_unknowns(), 6 + 2 + 1);
  std::vector<double> delta(l.num_unknowns());
  for (size_t j = 0; j < delta.size(); ++j) delta[j] = 100.0 * (j + 1);
  std::vector<double> out(p.cameras.size());
  l.Plus(p.cameras.data(), delta.data(), out.data());
  std::vector<double> expected = p.cameras;
  PlusPose(p.cameras.data(), delta.data(), expected.data());  // pose 0
  expected[12 + 1] += delta[6];                             // group 0: cx
  expected[12 + 2] += delta[7];                             //          cy
  expected[17 + 3] += delta[8];                             // group 1: k1
  EXPECT_EQ(out, expected);
  l.Plus(out.data(), delta.data(), out.data());  // in place
  EXPECT_EQ(out[20], p.cameras[20] + 2 * delta[8]);
}

TEST(UnknownLayout, ShareRowsMapToTheProblemRows) {
  Problem whole = PhotoCameras(6, 3);
  whole.fixed_cameras = {0, 0, 1, 0, 0, 0};
  const UnknownLayout global(whole);
  // A share holding images 2, 3, 5 (groups 2, 0, 2) renumbered 0, 1, 2 and
  // groups 0, 2 renumbered 0, 1.
  Problem share = PhotoCameras(3, 2);
  share.camera_intrinsics = {1, 0, 1};
  share.fixed_cameras = {1, 0, 0};
  const UnknownLayout local(share);
  const std::vector<int64_t> entities = local.RowEntities({2, 3, 5}, {0, 2});
  EXPECT_EQ(entities, (std::vector<int64_t>{3, 5, -1, -3}));
  EXPECT_EQ(global.RowsOfEntities(entities), (std::vector<int32_t>{2, 4, 5, 7}));
  EXPECT_THROW(global.RowsOfEntities({2}), std::logic_error);  // image 2 is fixed
}

}  // namespace
}  // namespace dba
