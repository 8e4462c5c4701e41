// ObservationResidual picks the problem's camera model and, for the
// photogrammetric one, the image's intrinsic group.
#include "dba/camera/observation_residual.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "dba/camera/photo_camera.h"
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

}  // namespace
}  // namespace dba
