// The range of an observed pixel at its edge and past it.
#include "dba/problem/pixel_range.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace dba {
namespace {

TEST(PixelOutOfRange, AnyImagesPixelIsInRangeAndTenTimesTheLargestIsNot) {
  EXPECT_EQ(PixelOutOfRange(0.0, 0.0), "");
  EXPECT_EQ(PixelOutOfRange(-332.65, 262.09), "");  // BAL, about the centre
  EXPECT_EQ(PixelOutOfRange(1e7, -1e7), "");
  EXPECT_EQ(PixelOutOfRange(1e80, 262.09),
            "pixel (1e+80, 262.09) is beyond 1e7 px from the origin: no image is that large");
  EXPECT_EQ(PixelOutOfRange(1.0, -1.00000001e7),
            "pixel (1, -10000000.1) is beyond 1e7 px from the origin: no image is that large");
  EXPECT_EQ(PixelOutOfRange(std::nan(""), 1.0), "pixel (nan, 1) is not finite");
  EXPECT_EQ(PixelOutOfRange(1.0, std::numeric_limits<double>::infinity()),
            "pixel (1, inf) is not finite");
}

}  // namespace
}  // namespace dba
