// ObservationResidual picks the problem's camera model and, for the
// photogrammetric one, the image's intrinsic group.
#include "dba/camera/observation_residual.h"

#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "dba/camera/photo_camera.h"
#include "dba/camera/rotation.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

TEST(ObservationResidual, BalModelIsBalResidual) {
  testing::SyntheticBalOptions o;
  o.pixel_noise = 1.0;
  const Problem p = testing::MakeSyntheticBal(o).problem;
  for (int64_t obs = 0; obs < p.num_observations(); ++obs) {
    const int32_t i = p.obs_camera[obs];
    const int64_t k = std::upper_bound(p.point_offsets.begin(), p.point_offsets.end(), obs) -
                      p.point_offsets.begin() - 1;
    EXPECT_EQ(ObservationResidual(p, p.cameras.data(), i, p.point(k), p.pixel(obs)),
              BalResidual(p.camera(i), p.point(k), p.pixel(obs)));
  }
}

TEST(ObservationResidual, PhotoModelUsesTheImagesGroup) {
  testing::SyntheticPhotoOptions o;
  o.geometry.pixel_noise = 1.0;
  o.num_groups = 3;
  const Problem p = testing::MakeSyntheticPhoto(o).problem;
  ASSERT_EQ(p.num_groups(), 3);
  const double X[3] = {0.1, -0.2, 0.3}, pixel[2] = {300.0, 200.0};
  for (int32_t i = 0; i < p.num_images(); ++i) {
    const Vec2 r = ObservationResidual(p, p.cameras.data(), i, X, pixel);
    EXPECT_EQ(r, PhotoResidual(LensModel::kRadial, p.camera(i), p.intrinsics(i % 3), X, pixel)) << i;
    if (i % 3 != 0) {
      EXPECT_NE(r, PhotoResidual(LensModel::kRadial, p.camera(i), p.intrinsics(0), X, pixel)) << i;
    }
  }
}

// The search runs over the threads in contiguous ranges of points: the
// count is every bad observation, and the ones kept are the first in
// observation order, whichever thread found them.
TEST(ScanResiduals, CountsAllNonFiniteAndKeepsTheFirstInObservationOrder) {
  testing::SyntheticBalOptions o;
  o.pixel_noise = 1.0;
  Problem p = testing::MakeSyntheticBal(o).problem;
  ASSERT_GE(p.num_points(), 20);
  EXPECT_EQ(ScanResiduals(p).non_finite, 0);
  // Points of no finite position, one early and several late in the point
  // order: every observation of theirs is bad.
  const std::vector<int64_t> bad_points = {3, p.num_points() - 9, p.num_points() - 5,
                                           p.num_points() - 2};
  int64_t bad_observations = 0;
  for (const int64_t k : bad_points) {
    p.point(k)[1] = std::nan("");
    bad_observations += p.point_offsets[k + 1] - p.point_offsets[k];
  }
  ASSERT_GE(bad_observations, 8);
  // Kept: all of point 3's and some of the next bad points' (found by other
  // threads), in observation order.
  const int keep = static_cast<int>(p.point_offsets[4] - p.point_offsets[3]) + 3;
  std::vector<int64_t> expected;
  for (const int64_t k : bad_points) {
    for (int64_t obs = p.point_offsets[k]; obs < p.point_offsets[k + 1]; ++obs) {
      if (static_cast<int>(expected.size()) < keep) expected.push_back(obs);
    }
  }
  const int before = omp_get_max_threads();
  // Walked in reverse too: the first in observation order all the same.
  std::vector<int64_t> reversed(static_cast<size_t>(p.num_points()));
  for (int64_t k = 0; k < p.num_points(); ++k) reversed[k] = p.num_points() - 1 - k;
  for (const int threads : {1, 2, 3, 8, -2}) {
    omp_set_num_threads(std::abs(threads));
    const ResidualScan bad = threads > 0 ? ScanResiduals(p, {}, keep) : ScanResiduals(p, reversed, keep);
    EXPECT_EQ(bad.non_finite, bad_observations) << threads;
    ASSERT_EQ(bad.first_non_finite.size(), expected.size()) << threads;
    for (size_t x = 0; x < expected.size(); ++x) {
      EXPECT_EQ(bad.first_non_finite[x].observation, expected[x]) << threads << " " << x;
      EXPECT_EQ(bad.first_non_finite[x].camera, p.obs_camera[expected[x]]) << threads << " " << x;
    }
    EXPECT_EQ(bad.first_non_finite[0].point, 3) << threads;
  }
  omp_set_num_threads(before);
}

// Points moved behind their cameras are counted once per observation, in
// both camera models (a BAL camera looks down -z), whatever the threads.
int64_t BehindByHand(const Problem& p) {
  int64_t behind = 0;
  for (int64_t k = 0; k < p.num_points(); ++k) {
    const Vec3 X(p.point(k)[0], p.point(k)[1], p.point(k)[2]);
    for (int64_t o = p.point_offsets[k]; o < p.point_offsets[k + 1]; ++o) {
      const double* c = p.camera(p.obs_camera[o]);
      const double z = (AngleAxisToRotation(Vec3(c[0], c[1], c[2])) * X)(2) + c[5];
      behind += p.model == CameraModel::kBal ? z >= 0 : z <= 0;
    }
  }
  return behind;
}

TEST(ScanResiduals, CountsObservationsBehindTheirCameras) {
  testing::SyntheticBalOptions bal_options;
  testing::SyntheticPhotoOptions photo_options;
  for (Problem p : {testing::MakeSyntheticBal(bal_options).problem,
                    testing::MakeSyntheticPhoto(photo_options).problem}) {
    EXPECT_EQ(ScanResiduals(p).behind_cameras, 0);
    // Mirror some points through their first camera's centre: behind it.
    for (int64_t k = 0; k < p.num_points(); k += 7) {
      const double* c = p.camera(p.obs_camera[p.point_offsets[k]]);
      const Mat3 R = AngleAxisToRotation(Vec3(c[0], c[1], c[2]));
      const Vec3 centre = -R.transpose() * Vec3(c[3], c[4], c[5]);
      const Vec3 X(p.point(k)[0], p.point(k)[1], p.point(k)[2]);
      const Vec3 mirrored = 2 * centre - X;
      for (int j = 0; j < 3; ++j) p.point(k)[j] = mirrored(j);
    }
    const int64_t expected = BehindByHand(p);
    ASSERT_GE(expected, p.num_points() / 7);
    const int before = omp_get_max_threads();
    for (const int threads : {1, 3}) {
      omp_set_num_threads(threads);
      EXPECT_EQ(ScanResiduals(p).behind_cameras, expected) << threads;
    }
    omp_set_num_threads(before);
  }
}

}  // namespace
}  // namespace dba
