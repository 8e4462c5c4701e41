// RenumberAtRandom: the same problem (every observation still pairs the same
// camera, point and pixel), in a new order drawn from the seed alone, each
// point's observations by camera.
#include "dba/problem/random_renumbering.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <vector>

namespace dba {
namespace {

// 6 BAL cameras (camera i's parameters all 10 i + j), 40 points seen by 2-4
// cameras each, pixels naming their observation; a prior on point 7.
Problem Small() {
  Problem p;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < kBalCameraSize; ++j) p.cameras.push_back(10.0 * i + j);
  }
  p.fixed_cameras.assign(6, 0);
  p.fixed_cameras[2] = 1;
  p.point_offsets.push_back(0);
  for (int k = 0; k < 40; ++k) {
    p.points.insert(p.points.end(), {double(k), 2.0 * k, 3.0 * k});
    for (int a = 0; a < 2 + k % 3; ++a) {
      p.obs_camera.push_back((k + 2 * a) % 6);
      p.obs_pixel.insert(p.obs_pixel.end(), {double(p.obs_camera.size()), double(-k)});
    }
    p.point_offsets.push_back(static_cast<int64_t>(p.obs_camera.size()));
  }
  PointPrior prior;
  prior.point = 7;
  prior.position[0] = 7.0;
  p.point_priors.push_back(prior);
  return p;
}

// Each observation as (camera's first parameter, point's x, pixel x, pixel
// y, camera fixed), sorted: what a renumbering must keep.
std::vector<std::array<double, 5>> Observations(const Problem& p) {
  std::vector<std::array<double, 5>> out;
  for (int64_t k = 0; k < p.num_points(); ++k) {
    for (int64_t o = p.point_offsets[k]; o < p.point_offsets[k + 1]; ++o) {
      const int32_t c = p.obs_camera[o];
      out.push_back({p.camera(c)[0], p.point(k)[0], p.pixel(o)[0], p.pixel(o)[1],
                     double(p.fixed_cameras[c])});
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

TEST(RenumberAtRandom, KeepsTheProblemChangesItsOrderAndDependsOnTheSeedAlone) {
  const Problem given = Small();
  Problem a = given, b = given, c = given;
  RenumberAtRandom(5, &a);
  RenumberAtRandom(5, &b);
  RenumberAtRandom(6, &c);
  EXPECT_EQ(Observations(a), Observations(given));
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.cameras, b.cameras);
  EXPECT_EQ(a.obs_camera, b.obs_camera);
  EXPECT_NE(a.points, given.points);
  EXPECT_NE(a.cameras, given.cameras);
  EXPECT_NE(a.points, c.points);
  for (int64_t k = 0; k < a.num_points(); ++k) {
    EXPECT_TRUE(std::is_sorted(a.obs_camera.begin() + a.point_offsets[k],
                               a.obs_camera.begin() + a.point_offsets[k + 1]));
  }
  ASSERT_EQ(a.point_priors.size(), 1u);
  EXPECT_EQ(a.point(a.point_priors[0].point)[0], 7.0);
}

}  // namespace
}  // namespace dba
