// Tests of ReadBal: the shared BAL files, point-major ordering, token layout,
// and an InputError with file, line and a useful phrase for malformed input.
#include "dba/io/bal_reader.h"

#include <bzlib.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "dba/common/error.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

std::string TempPath(const std::string& name) {
  return dba::testing::TempPath("bal_reader_test_" + name);
}

std::string WriteFile(const std::string& name, const std::string& bytes) {
  std::string path = TempPath(name);
  FILE* f = std::fopen(path.c_str(), "wb");
  EXPECT_NE(f, nullptr) << path;
  EXPECT_EQ(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
  EXPECT_EQ(std::fclose(f), 0);
  return path;
}

std::string Compress(const std::string& text) {
  std::vector<char> out(text.size() + text.size() / 100 + 1024);
  unsigned int len = static_cast<unsigned>(out.size());
  EXPECT_EQ(BZ2_bzBuffToBuffCompress(out.data(), &len, const_cast<char*>(text.data()),
                                     static_cast<unsigned>(text.size()), 9, 0, 0),
            BZ_OK);
  return std::string(out.data(), len);
}

void ExpectSameProblem(const Problem& a, const Problem& b) {
  EXPECT_EQ(a.cameras, b.cameras);
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.point_offsets, b.point_offsets);
  EXPECT_EQ(a.obs_camera, b.obs_camera);
  EXPECT_EQ(a.obs_pixel, b.obs_pixel);
}

// Ceres' AngleAxisRotatePoint.
void Rotate(const double* r, const double* x, double* y) {
  double theta = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
  double c[3];
  if (theta > 1e-12) {
    double k[3] = {r[0] / theta, r[1] / theta, r[2] / theta};
    double ct = std::cos(theta), st = std::sin(theta);
    double kx = k[0] * x[0] + k[1] * x[1] + k[2] * x[2];
    c[0] = k[1] * x[2] - k[2] * x[1];
    c[1] = k[2] * x[0] - k[0] * x[2];
    c[2] = k[0] * x[1] - k[1] * x[0];
    for (int i = 0; i < 3; ++i) y[i] = x[i] * ct + c[i] * st + k[i] * kx * (1 - ct);
  } else {
    c[0] = r[1] * x[2] - r[2] * x[1];
    c[1] = r[2] * x[0] - r[0] * x[2];
    c[2] = r[0] * x[1] - r[1] * x[0];
    for (int i = 0; i < 3; ++i) y[i] = x[i] + c[i];
  }
}

int64_t CountBehindCamera(const Problem& p) {
  int64_t behind = 0;
  for (int64_t k = 0; k < p.num_points(); ++k) {
    for (int64_t j = p.point_offsets[k]; j < p.point_offsets[k + 1]; ++j) {
      const double* cam = p.camera(p.obs_camera[j]);
      double y[3];
      Rotate(cam, p.point(k), y);
      if (y[2] + cam[5] >= 0) ++behind;
    }
  }
  return behind;
}

struct SharedFile {
  const char* name;
  int64_t cameras, points, observations;
};

TEST(BalReaderTest, ReadsEverySharedFileWithReadmeCounts) {
  const SharedFile files[] = {
      {"problem-49-7776-pre.txt.bz2", 49, 7776, 31843},
      {"problem-73-11032-pre.txt.bz2", 73, 11032, 46122},
      {"problem-21-11315-pre.txt.bz2", 21, 11315, 36455},
      {"problem-16-22106-pre.txt.bz2", 16, 22106, 83718},
      {"balbianello-5-544-from-bundler.txt.bz2", 5, 544, 1417},
  };
  for (const SharedFile& f : files) {
    SCOPED_TRACE(f.name);
    Problem p = ReadBal(std::string(DBA_SHARED_DATA_DIR "/bal/") + f.name);
    EXPECT_EQ(p.num_images(), f.cameras);
    EXPECT_EQ(p.num_points(), f.points);
    EXPECT_EQ(p.num_observations(), f.observations);
    ASSERT_EQ(static_cast<int64_t>(p.point_offsets.size()), f.points + 1);
    EXPECT_EQ(p.point_offsets.front(), 0);
    EXPECT_EQ(p.point_offsets.back(), f.observations);
    EXPECT_EQ(static_cast<int64_t>(p.obs_pixel.size()), 2 * f.observations);
    for (int64_t k = 0; k < p.num_points(); ++k) {
      ASSERT_LT(p.point_offsets[k], p.point_offsets[k + 1]) << "point " << k;
    }
    for (int32_t c : p.obs_camera) ASSERT_TRUE(c >= 0 && c < f.cameras);
    EXPECT_EQ(p.cameras.capacity(), p.cameras.size());
  }
}

TEST(BalReaderTest, ParsesValuesExactly) {
  Problem p = ReadBal(DBA_SHARED_DATA_DIR "/bal/problem-49-7776-pre.txt.bz2");
  // First lines of the file: "0 0 -3.326500e+02 2.620900e+02", "1 0 ...".
  EXPECT_EQ(p.obs_camera[0], 0);
  EXPECT_EQ(p.obs_pixel[0], -3.326500e+02);
  EXPECT_EQ(p.obs_pixel[1], 2.620900e+02);
  EXPECT_EQ(p.obs_camera[1], 1);
  EXPECT_EQ(p.cameras[0], 1.5741515942940262e-02);
  EXPECT_EQ(p.cameras[1], -1.2790936163850642e-02);
}

TEST(BalReaderTest, BehindCameraObservationsNeedNoSpecialCase) {
  for (const char* name : {"problem-49-7776-pre.txt.bz2", "problem-73-11032-pre.txt.bz2"}) {
    SCOPED_TRACE(name);
    Problem p = ReadBal(std::string(DBA_SHARED_DATA_DIR "/bal/") + name);
    EXPECT_EQ(CountBehindCamera(p), 31);
  }
}

// 2 cameras, 3 points, 5 observations listed out of point order.
const char kSmall[] =
    "2 3 5\n"
    "1 2 10 11\n"
    "0 0 12 13\n"
    "1 1 14 15\n"
    "0 2 16 17\n"
    "1 0 18 19\n"
    "0.1 0.2 0.3 1 2 3 500 -1e-3 2e-7\n"
    "-0.1 -0.2 -0.3 -1 -2 -3 600 0 0\n"
    "1 2 3\n4 5 6\n7 8 9\n";

TEST(BalReaderTest, StoresObservationsPointMajorInFileOrder) {
  Problem p = ReadBal(WriteFile("small.txt", kSmall));
  EXPECT_EQ(p.point_offsets, (std::vector<int64_t>{0, 2, 3, 5}));
  EXPECT_EQ(p.obs_camera, (std::vector<int32_t>{0, 1, 1, 1, 0}));
  EXPECT_EQ(p.obs_pixel, (std::vector<double>{12, 13, 18, 19, 14, 15, 10, 11, 16, 17}));
  EXPECT_EQ(p.cameras[6], 500);
  EXPECT_EQ(p.cameras[7], -1e-3);
  EXPECT_EQ(p.cameras[9], -0.1);
  EXPECT_EQ(p.points, (std::vector<double>{1, 2, 3, 4, 5, 6, 7, 8, 9}));
}

TEST(BalReaderTest, TokensMaySplitOverLinesAnyWay) {
  Problem reference = ReadBal(WriteFile("layout_ref.txt", kSmall));
  std::string one_line, one_per_line, ragged;
  int i = 0;
  for (char c : std::string(kSmall)) {
    bool space = c == ' ' || c == '\n';
    one_line += space ? ' ' : c;
    one_per_line += space ? '\n' : c;
    ragged += !space ? std::string(1, c) : (++i % 3 == 0) ? "\r\n\n\t " : "  \t";
  }
  ExpectSameProblem(ReadBal(WriteFile("layout_one_line.txt", one_line)), reference);
  ExpectSameProblem(ReadBal(WriteFile("layout_per_line.txt", one_per_line)), reference);
  ExpectSameProblem(ReadBal(WriteFile("layout_ragged.txt", ragged)), reference);
  ExpectSameProblem(ReadBal(WriteFile("layout_small.bz2.data", Compress(kSmall))),
                    reference);
}

struct BadCase {
  const char* name;
  std::string text;
  int64_t line;
  const char* phrase;
};

const std::string kCams = "0 0 0 0 0 0 1 0 0\n0 0 0 0 0 0 1 0 0\n";  // 2 cameras
// A valid 2-camera, 2-point, 3-observation file is kHead + kObs + kCams + kPts.
const std::string kHead = "2 2 3\n";
const std::string kObs = "0 0 1.5 -2.5\n1 0 3 4\n1 1 5 6\n";
const std::string kPts = "1 2 3\n4 5 6\n";

class BalReaderMalformedTest : public ::testing::TestWithParam<BadCase> {};

TEST_P(BalReaderMalformedTest, ThrowsInputErrorWithFileLineAndPhrase) {
  const BadCase& c = GetParam();
  for (bool bz2 : {false, true}) {
    std::string name = std::string("bad_") + c.name + (bz2 ? ".bz2" : ".txt");
    std::string path = WriteFile(name, bz2 ? Compress(c.text) : c.text);
    try {
      ReadBal(path);
      ADD_FAILURE() << name << ": no error";
    } catch (const InputError& e) {
      std::string msg = e.what();
      EXPECT_EQ(e.file(), path);
      EXPECT_NE(msg.find(name), std::string::npos) << msg;
      EXPECT_EQ(e.line(), c.line) << msg;
      EXPECT_NE(msg.find(":" + std::to_string(c.line) + ":"), std::string::npos) << msg;
      EXPECT_NE(msg.find(c.phrase), std::string::npos) << msg;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    BalReader, BalReaderMalformedTest,
    ::testing::Values(
        BadCase{"valid_control", kHead + kObs + kCams + kPts + "x\n", 9,
                "expected end of file after the last point coordinate, found 'x'"},
        BadCase{"cut_inside_last_number", kHead + kObs + kCams + "1 2 3\n4 5 6.2", 8,
                "the file ends inside this line (no line end after the last value): cut short?"},
        BadCase{"empty", "", 1, "expected header 'num_cameras num_points"},
        BadCase{"short_header", "2 2\n", 1, "found end of file"},
        BadCase{"non_numeric_count", "2 two 3\n", 1, "found 'two' (not an integer)"},
        BadCase{"count_overflow", "2 99999999999999999999 3\n", 1,
                "out of the 64-bit integer range"},
        BadCase{"zero_cameras", "0 2 3\n" + kObs, 1, "num_cameras must be positive, found 0"},
        BadCase{"negative_points", "2 -2 3\n" + kObs, 1, "num_points must be positive, found -2"},
        BadCase{"zero_observations", "2 2 0\n", 1, "num_observations must be positive"},
        BadCase{"cameras_beyond_int32", "3000000000 2 3\n", 1, "32-bit camera id limit"},
        BadCase{"more_points_than_observations", "2 5 3\n", 1,
                "every point needs an observation"},
        BadCase{"camera_index_out_of_range", kHead + "0 0 1 2\n2 0 3 4\n1 1 5 6\n", 3,
                "camera index 2 of observation 1 is out of range [0, 2)"},
        BadCase{"four_header_counts", "3 20 60 7\n0 0 1.0 2.0\n", 1,
                "the header's line has 1 more value(s) after 'num_cameras num_points "
                "num_observations': a BAL header holds exactly three"},
        BadCase{"negative_point_index", kHead + "0 0 1 2\n1 -1 3 4\n1 1 5 6\n", 3,
                "point index -1 of observation 1 is out of range [0, 2)"},
        BadCase{"point_index_out_of_range", kHead + "0 0 1 2\n1 0 3 4\n1 2 5 6\n", 4,
                "point index 2 of observation 2 is out of range"},
        BadCase{"fractional_index", kHead + "0 0 1 2\n1.0 0 3 4\n", 3,
                "found '1.0' (not an integer)"},
        BadCase{"non_numeric_pixel", kHead + "0 0 1 2\n1 0 3 4\n1 1 5 y\n", 4,
                "found 'y' (not a number)"},
        BadCase{"trailing_chars_in_value", kHead + "0 0 1 2\n1 0 3 4x\n", 3,
                "found '4x' (not a number)"},
        BadCase{"nan_pixel", kHead + "0 0 nan 2\n", 2, "non-finite value 'nan'"},
        BadCase{"pixel_beyond_any_image", kHead + "0 0 1 2\n1 0 3 4\n1 1 1e80 6\n", 4,
                "observation 2: pixel (1e+80, 6) is beyond 1e7 px from the origin: no image is "
                "that large"},
        BadCase{"inf_camera", kHead + kObs + "0 0 0 0 0 0 1 0 0\n0 0 0 inf 0 0 1 0 0\n", 6,
                "non-finite value 'inf'"},
        BadCase{"huge_value", kHead + kObs + kCams + "1 2 3\n4 5 1e999\n", 8,
                "out of the double range"},
        BadCase{"short_observations", kHead + "0 0 1 2\n1 0 3 4\n", 3,
                "expected observation 2 of 3 ('camera point x y'), found end of file"},
        BadCase{"short_cameras", kHead + kObs + "0 0 0 0 0 0 1 0 0\n0 0 0\n", 6,
                "expected 9 camera parameters for camera 1, found end of file"},
        BadCase{"short_points", kHead + kObs + kCams + "1 2 3\n4 5\n", 8,
                "expected 3 coordinates for point 1, found end of file"},
        BadCase{"trailing_garbage", kHead + kObs + kCams + kPts + "\n\n7 # extra\n", 11,
                "do the header counts match the data?"},
        BadCase{"header_too_few_observations",
                "2 2 2\n0 0 1.5 -2.5\n1 1 5 6\n0 1 3 4\n" + kCams + kPts, 7,
                "expected end of file after the last point coordinate, found '3'"},
        BadCase{"header_too_many_observations", "2 2 4\n" + kObs + kCams + kPts, 8,
                "expected 3 coordinates for point 0, found end of file"},
        BadCase{"point_without_observation", kHead + "0 0 1 2\n1 0 3 4\n0 0 5 6\n" + kCams + kPts,
                8, "point 1 has no observation"},
        BadCase{"int64_observation_count", "2 2 3000000000\n" + kObs, 4,
                "expected observation 3 of 3000000000 ('camera point x y'), found end "
                "of file"}),
    [](const ::testing::TestParamInfo<BadCase>& info) { return info.param.name; });

TEST(BalReaderTest, MissingFileIsAnInputError) {
  std::string path = TempPath("missing.txt");
  try {
    ReadBal(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace dba
