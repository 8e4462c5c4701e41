// Problem: ForEachArray lists every array (a field added without it would
// be missing from shares sent to ranks and from the memory figures).
#include "dba/problem/problem.h"

#include <gtest/gtest.h>

namespace dba {
namespace {

// Seven vectors and the model with the slots per group, then five more: a new
// field fails here first.
static_assert(sizeof(CameraSide) == sizeof(std::vector<double>) * 7 + alignof(std::vector<double>),
              "a new field of CameraSide must be added to its ForEachArray");
static_assert(sizeof(Problem) == sizeof(CameraSide) + sizeof(std::vector<double>) * 5,
              "a new field of Problem must be added to its ForEachArray");

TEST(Problem, ForEachArrayVisitsEveryArrayOnceInOrder) {
  Problem p;
  p.cameras.resize(1);
  p.group_models.resize(9);
  p.camera_intrinsics.resize(2);
  p.fixed_cameras.resize(3);
  p.fixed_intrinsics.resize(4);
  p.image_frame.resize(2);
  p.sensor_kind.resize(3);
  p.points.resize(5);
  p.point_offsets.resize(6);
  p.obs_camera.resize(7);
  p.obs_pixel.resize(8);
  p.point_priors.resize(2);
  std::vector<size_t> sizes;
  p.ForEachArray([&](const auto& v) { sizes.push_back(v.size()); });
  EXPECT_EQ(sizes, (std::vector<size_t>{1, 9, 2, 3, 4, 2, 3, 5, 6, 7, 8, 2}));
  const int64_t camera_side = 1 * 8 + 9 + 2 * 4 + 3 + 4 * 2 + 2 * 4 + 3;
  const int64_t expected =
      camera_side + 5 * 8 + 6 * 8 + 7 * 4 + 8 * 8 + 2 * int64_t{sizeof(PointPrior)};
  int64_t capacities = 0;
  p.ForEachArray([&](const auto& v) { capacities += static_cast<int64_t>(v.capacity()); });
  ASSERT_EQ(capacities, 52);  // resize of an empty vector: capacity == size
  EXPECT_EQ(p.MemoryBytes(), expected);
  EXPECT_EQ(p.camera_side().MemoryBytes(), camera_side);
}

}  // namespace
}  // namespace dba
