// The --gcps file: what it reads, and every refusal with file and line.
#include "dba/io/ground_control_file.h"

#include <gtest/gtest.h>

#include "dba/common/error.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

std::string Write(const std::string& text) {
  const std::string path = testing::TempPath("g.txt");
  EXPECT_TRUE(testing::WriteFileBytes(path, text));
  return path;
}

// The message of the InputError reading `text` throws.
std::string ErrorOf(const std::string& text) {
  try {
    ReadGroundControlFile(Write(text));
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(GroundControlFile, ReadsPointsAndTheirMeasurementsInAnyOrder) {
  const auto rows = ReadGroundControlFile(Write(
      "# a comment\n"
      "A 7 3 0.5 0.01 0.03 control  # measured below\n"
      "A img1.jpg 10 20\n"
      "B, 1, 2, 3, 0.02, 0.05, check\n"
      "B 0 1.5 2.5\n"
      "\n"
      "B 4 3.5 -4.5\n"
      "A img2.jpg 11 21\n"));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].name, "A");
  EXPECT_TRUE(rows[0].control);
  EXPECT_EQ(rows[0].xyz, Eigen::Vector3d(7, 3, 0.5));
  EXPECT_EQ(rows[0].sigma, Eigen::Vector2d(0.01, 0.03));
  ASSERT_EQ(rows[0].measurements.size(), 2u);
  EXPECT_EQ(rows[0].measurements[1].image, "img2.jpg");
  EXPECT_EQ(rows[0].measurements[1].pixel, Eigen::Vector2d(11, 21));
  EXPECT_EQ(rows[0].measurements[1].line, 8);
  EXPECT_FALSE(rows[1].control);
  EXPECT_EQ(rows[1].sigma, Eigen::Vector2d(0.02, 0.05));
  EXPECT_EQ(rows[1].measurements[1].pixel, Eigen::Vector2d(3.5, -4.5));
}

TEST(GroundControlFile, RefusesBadInputWithFileAndLine) {
  const std::string point = "A 1 2 3 0.02 0.02 control\nA 0 1 2\n";
  struct Case {
    std::string text, message;
  };
  const Case cases[] = {
      {"A 1 2 3 0.02 control\n", "g.txt:1: expected a point, NAME X Y Z SIGMA_XY SIGMA_Z"},
      {"A 1 2 nan 0.02 0.02 control\n", "g.txt:1: Z: 'nan' is not a finite number"},
      {"A 1 2 3 0 0.02 control\n", "g.txt:1: sigma must be within [1e-06, 1e+06]"},
      {"A 1 2 3 1e-300 0.02 control\n", "g.txt:1: sigma must be within [1e-06, 1e+06]"},
      {"A 1 2 3 0.02 1e7 control\n", "g.txt:1: sigma must be within"},
      {"A 1 2 3 0.02 -1 control\n", "g.txt:1: sigma must be within"},
      {"A 1 2 3 0.02 0.02 tie\n", "g.txt:1: role 'tie': expected control or check"},
      {point + "A 4 5 6 0.02 0.02 check\n", "g.txt:3: point 'A' is already defined (line 1)"},
      {point + "B 0 1 2\n", "g.txt:3: measurement of 'B', which no line"},
      {point + "A 0 5 5\n", "g.txt:3: point 'A' is already measured in image '0' (line 2)"},
      {point + "A 1 x 5\n", "g.txt:3: x: 'x' is not a finite number"},
      {point + "A 1 5 -3e7\n",
       "g.txt:3: measurement: pixel (5, -30000000) is beyond 1e7 px from the origin"},
      {"A 1 2 3 0.02 0.02 check\nA 0 1 2\n", "g.txt:1: check point 'A' is measured in 1 image(s)"},
      {"A 1 2 3 0.02 0.02 control\n", "g.txt:1: control point 'A' is measured in 0 image(s)"},
      {"# nothing\n", "g.txt: no points"},
  };
  for (const Case& c : cases) {
    EXPECT_NE(ErrorOf(c.text).find(c.message), std::string::npos)
        << "for:\n" << c.text << "got: " << ErrorOf(c.text);
  }
}

}  // namespace
}  // namespace dba
