// A free FOV ω in COLMAP's series branch starts at ±0.01; nothing else moves.
#include "dba/camera/fov_series_start.h"

#include <gtest/gtest.h>

#include "dba/camera/lens_projection.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

TEST(StartFovOutsideSeries, MovesFreeOmegaInTheSeriesBranchOnly) {
  testing::SyntheticPhotoOptions o;
  o.geometry.num_cameras = 6;
  o.geometry.num_points = 30;
  o.num_groups = 6;
  o.lens_model = LensModel::kFov;
  Problem p = testing::MakeSyntheticPhoto(o).problem;
  ASSERT_EQ(p.num_groups(), 6);
  p.group_models[5] = LensModel::kRadial;
  const double omegas[6] = {0.001, -0.005, 0.0, 0.01, 0.0099, 0.0099};
  for (int g = 0; g < 6; ++g) p.intrinsics(g)[4] = omegas[g];
  p.fixed_intrinsics.assign(6, 0);
  p.fixed_intrinsics[4] = 1u << 4;  // group 4's ω held: left where it is
  const std::vector<FovStartMove> moves = StartFovOutsideSeries(&p);
  ASSERT_EQ(moves.size(), 3u);
  EXPECT_EQ(moves[0].group, 0);
  EXPECT_EQ(moves[0].from, 0.001);
  EXPECT_EQ(p.intrinsics(0)[4], 0.01);
  EXPECT_EQ(moves[1].group, 1);
  EXPECT_EQ(p.intrinsics(1)[4], -0.01);  // the sign kept (the model is even in ω)
  EXPECT_EQ(moves[2].group, 2);
  EXPECT_EQ(p.intrinsics(2)[4], 0.01);
  EXPECT_EQ(p.intrinsics(3)[4], 0.01);    // on the closed form already
  EXPECT_EQ(p.intrinsics(4)[4], 0.0099);  // fixed
  EXPECT_EQ(p.intrinsics(5)[4], 0.0099);  // RADIAL's k2, not an ω
  EXPECT_NE(DescribeFovStartMoves(moves).find("FOV group 1: omega -0.0050000000000000001 starts at -0.01"),
            std::string::npos)
      << DescribeFovStartMoves(moves);
}

// ±0.01 is on COLMAP's closed-form branch (ω² ≥ 1e-4 in doubles), where
// ω > 0 bends a point at |n| = 1 inwards (barrel), and the series just
// inside the boundary bends it outwards: why ω = 0 is a false minimum there.
TEST(StartFovOutsideSeries, TheStartIsOnTheClosedFormWhichBendsTheOtherWay) {
  EXPECT_GE(kFovClosedFormOmega * kFovClosedFormOmega, 1e-4);
  const double inside = 0.0099999;
  EXPECT_LT(inside * inside, 1e-4);
  const Eigen::Vector3d P(1.0, 0.0, 1.0);  // |n| = 1
  auto u = [&](double omega) {
    const double params[5] = {1.0, 1.0, 0.0, 0.0, omega};
    return LensProject(LensModel::kFov, params, P, nullptr, nullptr)(0);
  };
  EXPECT_LT(u(kFovClosedFormOmega), 1.0);  // closed form: σ < 1
  EXPECT_GT(u(inside), 1.0);               // COLMAP's series: σ > 1
}

}  // namespace
}  // namespace dba
