// Each rule of the lens parameters' ranges, at its edge and past it.
#include "dba/problem/lens_ranges.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace dba {
namespace {

std::string Check(LensModel m, std::vector<double> params) {
  EXPECT_EQ(static_cast<int>(params.size()), LensModelParams(m));
  return LensValueOutOfRange(m, params.data());
}

TEST(LensValueOutOfRange, EveryModelsTypicalCameraIsInRange) {
  for (const LensModelInfo& m : LensModels()) {
    std::vector<double> params(static_cast<size_t>(m.num_params), 0.0);
    for (int j = 0; j < m.num_params; ++j) {
      const std::string name = LensModelParamName(m.id, j);
      if (name == "f" || name == "fx" || name == "fy") params[j] = 700;
      if (name == "cx" || name == "w") params[j] = 640;
      if (name == "cy" || name == "h") params[j] = 360;
      if (name == "alpha" || name == "beta") params[j] = 0.5;
      if (name == "omega") params[j] = 1.0;
    }
    EXPECT_EQ(LensValueOutOfRange(m.id, params.data()), "") << m.name;
  }
}

TEST(LensValueOutOfRange, EachRuleAtItsEdge) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(Check(LensModel::kPinhole, {700, 0, 640, 360}),
            "PINHOLE's fy is 0: it must be > 0 (a focal length)");
  EXPECT_EQ(Check(LensModel::kSimpleRadial, {1e-300, 640, 360, 0}), "");
  EXPECT_EQ(Check(LensModel::kSimpleRadial, {700, 640, 360, nan}),
            "SIMPLE_RADIAL's k is nan: it is not finite");
  EXPECT_EQ(Check(LensModel::kFov, {700, 700, 640, 360, -3.14}), "");
  EXPECT_EQ(Check(LensModel::kFov, {700, 700, 640, 360, std::numbers::pi}),
            "FOV's omega is 3.1415926535897931: it must be within (-pi, pi) (the lens's field of "
            "view, radians)");
  EXPECT_EQ(Check(LensModel::kEucm, {700, 700, 640, 360, 0, 1e-9}), "");
  EXPECT_EQ(Check(LensModel::kEucm, {700, 700, 640, 360, 1, 1}), "");
  EXPECT_EQ(Check(LensModel::kEucm, {700, 700, 640, 360, 1.0000001, 1}),
            "EUCM's alpha is 1.0000001000000001: it must be within [0, 1]");
  EXPECT_EQ(Check(LensModel::kEucm, {700, 700, 640, 360, 0.5, 0}),
            "EUCM's beta is 0: it must be > 0");
  EXPECT_EQ(Check(LensModel::kEquirectangular, {1, 1}), "");
  EXPECT_EQ(Check(LensModel::kEquirectangular, {1280, 0.5}),
            "EQUIRECTANGULAR's h is 0.5: it must be >= 1 (the panorama's size in pixels)");
  // Distortion has no physical sign: any finite value is a lens.
  EXPECT_EQ(Check(LensModel::kDivision, {700, 700, 640, 360, -1e6}), "");
}

}  // namespace
}  // namespace dba
