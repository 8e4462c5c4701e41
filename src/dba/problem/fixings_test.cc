// ApplyFixings with rigs: a held image holds its frame (the layout's rule)
// and its sensor, whether the command line or the problem's own flags hold
// it; an image of the rig's origin sensor leaves the other sensors refined.
#include "dba/problem/fixings.h"

#include <gtest/gtest.h>

#include "dba/rcs/unknown_layout.h"
#include "dba/testing/synthetic_rig.h"

namespace dba {
namespace {

Problem Rig() {
  testing::SyntheticRigOptions o;
  o.sensors = 3;
  return testing::MakeSyntheticRig(o).problem;  // image 3f + s: frame f, sensor s
}

TEST(FixingsRigs, AHeldImageHoldsItsFrameAndItsSensor) {
  Problem p = Rig();
  ASSERT_EQ(p.sensor_kind, (std::vector<uint8_t>{kRigOrigin, kSensorRefined, kSensorRefined}));
  Fixings f;
  f.images = {4};  // frame 1, sensor 1
  ApplyFixings(f, &p);
  EXPECT_EQ(p.sensor_kind, (std::vector<uint8_t>{kRigOrigin, kSensorHeld, kSensorRefined}));
  // Frame 1 is no unknown: 5 frame rows, image 4 on none; sensor 2's
  // intrinsics row holds its pose's 6 unknowns more than sensor 1's.
  const UnknownLayout layout(p);
  EXPECT_EQ(layout.num_camera_rows(), 5);
  EXPECT_EQ(layout.rows_of_image(p, 4).camera, -1);
  const int32_t r1 = layout.rows_of_image(p, 4).intrinsics, r2 = layout.rows_of_image(p, 5).intrinsics;
  EXPECT_EQ(layout.block_size(r2) - layout.intrinsic_unknowns(r2), 6);
  EXPECT_EQ(layout.block_size(r1), layout.intrinsic_unknowns(r1));

  Problem flagged = Rig();  // held by the problem's own flags (a .dba's)
  flagged.fixed_cameras.assign(flagged.num_images(), 0);
  flagged.fixed_cameras[5] = 1;  // frame 1, sensor 2
  ApplyFixings(Fixings{}, &flagged);
  EXPECT_EQ(flagged.sensor_kind, (std::vector<uint8_t>{kRigOrigin, kSensorRefined, kSensorHeld}));

  Problem origin = Rig();
  f.images = {3};  // frame 1, the origin: the frame alone
  ApplyFixings(f, &origin);
  EXPECT_EQ(origin.sensor_kind, (std::vector<uint8_t>{kRigOrigin, kSensorRefined, kSensorRefined}));
}

}  // namespace
}  // namespace dba
