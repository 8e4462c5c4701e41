#include "dba/precision/external_datum.h"

#include <gtest/gtest.h>

namespace dba {
namespace {

std::vector<SurveyedPosition> Along(const Vec3& direction, double off, int n) {
  std::vector<SurveyedPosition> at;
  for (int i = 0; i < n; ++i) {
    const Vec3 side = Vec3(0.0, 0.0, 1.0).cross(direction).normalized();
    at.push_back({Vec3(5, -3, 100) + 20.0 * i * direction + off * (i % 2 ? 1.0 : -1.0) * side, 0.02});
  }
  return at;
}

TEST(FrameLeftFreeBy, AStripWithinItsSigmaLeavesTheRollAboutIt) {
  const std::string free = FrameLeftFreeBy(Along(Vec3(1, 1, 0).normalized(), 0.03, 12));
  EXPECT_NE(free.find("12 surveyed positions lie along one line (0.0297 m RMS off it, sigma 0.02 m)"),
            std::string::npos)
      << free;
}

TEST(FrameLeftFreeBy, AStripWiderThanThreeSigmaHoldsTheFrame) {
  EXPECT_EQ(FrameLeftFreeBy(Along(Vec3(1, 1, 0).normalized(), 0.07, 12)), "");
}

TEST(FrameLeftFreeBy, OnePlaceLeavesTheRotationAndTheScale) {
  const std::string free = FrameLeftFreeBy({{Vec3(1, 2, 3), 0.02}, {Vec3(1.01, 2, 3), 0.02}});
  EXPECT_NE(free.find("lie within 0.005 m of one place (sigma 0.02 m): the rotation and the scale"),
            std::string::npos)
      << free;
  EXPECT_NE(FrameLeftFreeBy({{Vec3(1, 2, 3), 0.02}}), "");
}

TEST(FrameLeftFreeBy, NothingSurveyedIsNotThisCheck) { EXPECT_EQ(FrameLeftFreeBy({}), ""); }

}  // namespace
}  // namespace dba
