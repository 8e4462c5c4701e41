// Tests of the COLMAP text reader and writer: read -> write -> read is exact
// on every shared model (binary ones included), the written files have
// COLMAP's headers and layout, and malformed input is refused with file:line.
#include "dba/testing/temp_files.h"
#include "dba/io/colmap_text.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "dba/common/error.h"

namespace dba {
namespace {

namespace fs = std::filesystem;

const char* const kSharedModels[] = {"statue_of_liberty", "statue_of_liberty_small_txt",
                                     "fountain_p11", "softmurata_177img",
                                     "mithunnallana_6img"};

std::string SharedDir(const char* folder) {
  return std::string(DBA_SHARED_DATA_DIR) + "/colmap/" + folder + "/sparse/0";
}

// A fresh directory, private to this process and removed when it exits.
std::string TempDir(const std::string& name) {
  return dba::testing::FreshTempDir(name);
}

std::string ReadBytes(const std::string& path) {
  EXPECT_TRUE(std::filesystem::exists(path)) << path;
  return dba::testing::ReadFileBytes(path);
}

void WriteBytes(const std::string& path, const std::string& bytes) {
  EXPECT_TRUE(dba::testing::WriteFileBytes(path, bytes)) << path;
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

template <typename F>
std::string ExpectInputError(F f, const std::vector<std::string>& phrases) {
  try {
    f();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string& p : phrases) {
      EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
    }
    return msg;
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

const char kCameras[] =
    "# Camera list with one line of data per camera:\n"
    "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
    "# Number of cameras: 1\n"
    "1 SIMPLE_RADIAL 640 480 500 320 240 -0.1\n";
const char kImages[] =
    "# Image list with two lines of data per image:\n"
    "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
    "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
    "# Number of images: 3, mean observations per image: 1.3333333333333333\n"
    "1 1 0 0 0 0 0 0 1 a.jpg\n"
    "10 20 7 30 40 -1\n"
    "2 1 0 0 0 1 0 0 1 b.jpg\n"
    "11 21 7 31 41 8\n"
    "3 1 0 0 0 2 0 0 1 c.jpg\n"
    "12 22 8\n";
const char kPoints[] =
    "# 3D point list with one line of data per point:\n"
    "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
    "# Number of points: 2, mean track length: 2\n"
    "7 0 0 5 255 0 0 0.5 1 0 2 0\n"
    "8 1 0 5 0 255 0 0.25 2 1 3 0\n";

// A tiny model in `dir` with the given files (defaults above).
std::string TinyDir(const std::string& name, const std::string& cameras = kCameras,
                    const std::string& images = kImages, const std::string& points = kPoints) {
  const std::string dir = TempDir(name);
  WriteBytes(dir + "/cameras.txt", cameras);
  WriteBytes(dir + "/images.txt", images);
  WriteBytes(dir + "/points3D.txt", points);
  return dir;
}

TEST(ColmapTextTest, RoundTripIsExactOnEverySharedModel) {
  for (const char* folder : kSharedModels) {
    SCOPED_TRACE(folder);
    const ColmapModel original = ReadColmapModel(SharedDir(folder));
    const std::string dir = TempDir(std::string("round_") + folder);
    WriteColmapText(original, dir);
    const ColmapModel reread = ReadColmapText(dir);
    ASSERT_EQ(FirstColmapModelDifference(original, reread), "");
    EXPECT_EQ(original, reread);

    // Writing what was read back gives the same bytes again.
    const std::string dir2 = TempDir(std::string("round2_") + folder);
    WriteColmapText(reread, dir2);
    for (const char* f : {"cameras.txt", "images.txt", "points3D.txt"}) {
      EXPECT_EQ(ReadBytes(dir + "/" + f), ReadBytes(dir2 + "/" + f)) << f;
    }
    // No temporaries left behind.
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
      EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
      ++files;
    }
    EXPECT_EQ(files, 3u);
  }
}

TEST(ColmapTextTest, SharedTextModelsReadWithTheirOwnLines) {
  // The original files' data lines, re-tokenised, equal the written ones
  // number for number (values compared as doubles, not as text).
  for (const char* folder : {"statue_of_liberty_small_txt", "mithunnallana_6img"}) {
    SCOPED_TRACE(folder);
    const ColmapModel m = ReadColmapText(SharedDir(folder));
    const std::string dir = TempDir(std::string("lines_") + folder);
    WriteColmapText(m, dir);
    for (const char* f : {"cameras.txt", "images.txt", "points3D.txt"}) {
      std::string in = ReadBytes(SharedDir(folder) + "/" + f);
      std::erase(in, '\r');
      const std::vector<std::string> a = Lines(in);
      const std::vector<std::string> b = Lines(ReadBytes(dir + "/" + f));
      ASSERT_EQ(a.size(), b.size()) << f;
      for (size_t i = 0; i < a.size(); ++i) {
        if (a[i].starts_with("#")) continue;
        std::istringstream sa(a[i]), sb(b[i]);
        std::vector<std::string> ta, tb;
        for (std::string t; sa >> t;) ta.push_back(t);
        for (std::string t; sb >> t;) tb.push_back(t);
        ASSERT_EQ(ta.size(), tb.size()) << f << " line " << i + 1;
        for (size_t k = 0; k < ta.size(); ++k) {
          char* end_a = nullptr;
          char* end_b = nullptr;
          const double va = std::strtod(ta[k].c_str(), &end_a);
          const double vb = std::strtod(tb[k].c_str(), &end_b);
          if (*end_a == '\0' && *end_b == '\0') {
            ASSERT_EQ(va, vb) << f << " line " << i + 1 << " token " << k;
          } else {
            ASSERT_EQ(ta[k], tb[k]) << f << " line " << i + 1 << " token " << k;
          }
        }
      }
    }
  }
}

TEST(ColmapTextTest, WritesColmapsHeadersAndLayout) {
  const ColmapModel m = ReadColmapText(SharedDir("statue_of_liberty_small_txt"));
  const std::string dir = TempDir("headers");
  WriteColmapText(m, dir);
  const std::vector<std::string> cameras = Lines(ReadBytes(dir + "/cameras.txt"));
  ASSERT_EQ(cameras.size(), 4u);
  EXPECT_EQ(cameras[0], "# Camera list with one line of data per camera:");
  EXPECT_EQ(cameras[1], "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]");
  EXPECT_EQ(cameras[2], "# Number of cameras: 1");
  EXPECT_EQ(cameras[3], "1 SIMPLE_RADIAL 800 1200 2395.65 400 600 -0.684122");

  const std::vector<std::string> images = Lines(ReadBytes(dir + "/images.txt"));
  ASSERT_EQ(images.size(), 4u + 2 * 40);
  EXPECT_EQ(images[0], "# Image list with two lines of data per image:");
  EXPECT_EQ(images[1], "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME");
  EXPECT_EQ(images[2], "#   POINTS2D[] as (X, Y, POINT3D_ID)");
  EXPECT_EQ(images[3], "# Number of images: 40, mean observations per image: 194");
  EXPECT_EQ(images[4],
            "1 0.842381 0.215061 0.44459 -0.215599 -2.67344 3.07749 0.697147 1 "
            "14268549464_8c6bd2338d_o.jpg");
  EXPECT_TRUE(images[5].starts_with("213.271 57.3046 -1 213.271 57.3046 -1 "));
  EXPECT_NE(images[5].back(), ' ');

  const std::vector<std::string> points = Lines(ReadBytes(dir + "/points3D.txt"));
  ASSERT_EQ(points.size(), 3u + 1816);
  EXPECT_EQ(points[0], "# 3D point list with one line of data per point:");
  EXPECT_EQ(points[1],
            "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)");
  EXPECT_EQ(points[2], "# Number of points: 1816, mean track length: 4.273127753303965");
  EXPECT_EQ(points[3],
            "2395 -2.4176671939504706 0.05723246708798755 5.474169035132195 225 226 228 "
            "2.6191815037510193 35 853 20 767");
}

TEST(ColmapTextTest, TinyModelReadsAndRoundTrips) {
  const std::string dir = TinyDir("tiny");
  const ColmapModel m = ReadColmapText(dir);
  ASSERT_EQ(m.cameras.size(), 1u);
  EXPECT_EQ(m.cameras[0].ModelName(), "SIMPLE_RADIAL");
  EXPECT_EQ(m.cameras[0].width, 640u);
  EXPECT_EQ(m.cameras[0].params, (std::vector<double>{500, 320, 240, -0.1}));
  ASSERT_EQ(m.images.size(), 3u);
  EXPECT_EQ(m.images[1].name, "b.jpg");
  EXPECT_EQ(m.images[1].tvec[0], 1.0);
  ASSERT_EQ(m.images[0].points2D.size(), 2u);
  EXPECT_EQ(m.images[0].points2D[1].point3D_id, kColmapNoPoint3D);
  EXPECT_EQ(m.images[1].points2D[1].point3D_id, 8);
  ASSERT_EQ(m.points3D.size(), 2u);
  EXPECT_EQ(m.points3D[1].rgb, (std::array<uint8_t, 3>{0, 255, 0}));
  EXPECT_EQ(m.points3D[1].track, (std::vector<ColmapTrackElement>{{2, 1}, {3, 0}}));

  // Written back, the tiny files are reproduced byte for byte: they are in
  // COLMAP's layout with shortest numbers already.
  const std::string out = TempDir("tiny_out");
  WriteColmapText(m, out);
  EXPECT_EQ(ReadBytes(out + "/cameras.txt"), kCameras);
  EXPECT_EQ(ReadBytes(out + "/images.txt"), kImages);
  EXPECT_EQ(ReadBytes(out + "/points3D.txt"), kPoints);
}

TEST(ColmapTextTest, AcceptsCrlfTabsNamesWithSpacesAndImagesWithoutPoints) {
  const std::string images =
      "# comment\r\n"
      "\r\n"
      "1\t1 0 0 0 0 0 0 1   my photo 1.jpg  \r\n"
      "10 20 7 30 40 -1\r\n"
      "2 1 0 0 0 1 0 0 1 b.jpg\r\n"
      "11 21 7 31 41 18446744073709551615\r\n"
      "3 1 0 0 0 2 0 0 1 empty.jpg\r\n"
      "\r\n"
      "4 1 0 0 0 2 0 0 1 c.jpg\r\n"
      "12 22 7\r\n";
  const std::string points = "7 0 0 5 255 0 0 0.5 1 0 2 0 4 0\r\n";
  const std::string dir = TinyDir("crlf", kCameras, images, points);
  const ColmapModel m = ReadColmapText(dir);
  ASSERT_EQ(m.images.size(), 4u);
  EXPECT_EQ(m.images[0].name, "my photo 1.jpg");
  EXPECT_EQ(m.images[1].points2D[1].point3D_id, kColmapNoPoint3D);
  EXPECT_TRUE(m.images[2].points2D.empty());
  EXPECT_EQ(m.images[3].points2D.size(), 1u);

  const std::string out = TempDir("crlf_out");
  WriteColmapText(m, out);
  EXPECT_EQ(ReadColmapText(out), m);
  const std::vector<std::string> lines = Lines(ReadBytes(out + "/images.txt"));
  ASSERT_EQ(lines.size(), 4u + 8);
  EXPECT_EQ(lines[4], "1 1 0 0 0 0 0 0 1 my photo 1.jpg");
  EXPECT_EQ(lines[9], "");  // the empty POINTS2D line of empty.jpg
}

TEST(ColmapTextTest, ExactForAwkwardDoubles) {
  ColmapModel m = ReadColmapText(TinyDir("awkward"));
  const double values[] = {0.1, 1.0 / 3.0, -0.0, 5e-324, 1.7976931348623157e308,
                           2.2250738585072014e-308, 123456789.123456789, -1e-17};
  m.points3D[0].xyz = {values[0], values[1], values[2]};
  m.points3D[1].xyz = {values[3], values[4], values[5]};
  m.images[2].tvec = {values[6], values[7], std::nextafter(1.0, 2.0)};
  m.cameras[0].params[3] = std::nextafter(-0.1, 0.0);
  const std::string out = TempDir("awkward_out");
  WriteColmapText(m, out);
  EXPECT_EQ(FirstColmapModelDifference(ReadColmapText(out), m), "");
}

TEST(ColmapTextTest, OpencvIsReadAsItsLensModel) {
  const std::string cameras = "1 OPENCV 640 480 500 501 320 240 0.1 0.01 0.001 0.002\n";
  const std::string dir = TinyDir("opencv", cameras);
  const ColmapModel m = ReadColmapModel(dir);
  ASSERT_EQ(m.cameras[0].ModelName(), "OPENCV");
  EXPECT_EQ(m.cameras[0].params.size(), 8u);
  EXPECT_EQ(LensModelOfColmapCamera(m.cameras[0], dir + "/cameras.txt"), LensModel::kOpenCV);
  // And it round-trips like any other model.
  const std::string out = TempDir("opencv_out");
  WriteColmapText(m, out);
  EXPECT_EQ(ReadColmapText(out), m);
}

TEST(ColmapTextTest, MalformedLinesAreRefusedWithFileAndLine) {
  struct Case {
    const char* name;
    std::string cameras, images, points;
    std::vector<std::string> phrases;
  };
  const std::string c = kCameras, i = kImages, p = kPoints;
  auto replace = [](std::string s, const std::string& from, const std::string& to) {
    const size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  };
  const Case cases[] = {
      {"non-numeric QX", c, replace(i, "2 1 0 0 0 1", "2 1 x 0 0 1"), p,
       {"images.txt:7: ", "expected QX (a number), found 'x'"}},
      {"unknown model", replace(c, "SIMPLE_RADIAL", "SIMPLE_RADIALX"), i, p,
       {"cameras.txt:4: ", "unknown camera model 'SIMPLE_RADIALX'", "OPENCV"}},
      {"too few params", replace(c, " -0.1\n", "\n"), i, p,
       {"cameras.txt:4: ", "SIMPLE_RADIAL has 4 parameters (f, cx, cy, k), the line has 3"}},
      {"too many params", replace(c, " -0.1\n", " -0.1 7\n"), i, p,
       {"cameras.txt:4: ", "the line has 5"}},
      {"negative width", replace(c, " 640 ", " -640 "), i, p,
       {"cameras.txt:4: ", "expected WIDTH (an integer"}},
      {"camera id too large", replace(c, "\n1 SIMPLE", "\n4294967296 SIMPLE"), i, p,
       {"cameras.txt:4: ", "CAMERA_ID (an integer from 0 to 4294967295)"}},
      {"missing name", c, replace(i, " 1 b.jpg", " 1"), p,
       {"images.txt:7: ", "expected NAME"}},
      {"missing camera id", c, replace(i, " 0 0 1 b.jpg", " 0 0"), p,
       {"images.txt:7: ", "expected CAMERA_ID, found the end of the line"}},
      {"incomplete 2D point", c, replace(i, "31 41 8\n", "31 41\n"), p,
       {"images.txt:8: ", "expected POINT3D_ID of a 2D point"}},
      {"bad point3D ref", c, replace(i, "31 41 8\n", "31 41 -2\n"), p,
       {"images.txt:8: ", "(-1 or a point3D_id), found '-2'"}},
      {"nan coordinate", c, replace(i, "31 41 8\n", "31 nan 8\n"), p,
       {"images.txt:8: ", "Y of a 2D point is not finite"}},
      {"trailing garbage on number", c, i, replace(p, "0 0.5 1 0", "0 0.5x 1 0"),
       {"points3D.txt:4: ", "expected ERROR (a number), found '0.5x'"}},
      {"colour out of range", c, i, replace(p, "255 0 0", "256 0 0"),
       {"points3D.txt:4: ", "expected R (an integer from 0 to 255), found '256'"}},
      {"odd track", c, i, replace(p, "0.25 2 1 3 0\n", "0.25 2 1 3\n"),
       {"points3D.txt:5: ", "expected POINT2D_IDX of a track element"}},
      {"track to missing image", c, i, replace(p, "0.25 2 1 3 0\n", "0.25 2 1 9 0\n"),
       {"points3D.txt:5: ", "point3D 8: track element 1 (image 9", "no such image"}},
      {"track not pointing back", c, i, replace(p, "0.5 1 0 2 0", "0.5 1 1 2 0"),
       {"points3D.txt:4: ", "refers to point3D_id -1, not back"}},
      {"2D point not in a track", c, i, replace(p, "0.25 2 1 3 0\n", "0.25 2 1\n"),
       {"images.txt:10: ", "image 3: point2D 0 refers to point3D_id 8",
        "track does not list"}},
      {"image with missing camera", c, replace(i, " 0 0 1 c.jpg", " 0 0 2 c.jpg"), p,
       {"images.txt:9: ", "camera_id 2 is not in"}},
      {"duplicate point", c, i, replace(p, "\n8 1 0 5", "\n7 1 0 5"),
       {"points3D.txt:5: ", "point3D 7: point3D_id appears twice"}},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.name);
    const std::string dir = TinyDir("malformed", k.cameras, k.images, k.points);
    const std::string msg = ExpectInputError([&] { ReadColmapText(dir); }, k.phrases);
    EXPECT_EQ(msg.rfind(dir + "/", 0), 0u) << msg;  // starts with the full path
  }
}

TEST(ColmapTextTest, MissingFileIsNamed) {
  const std::string dir = TinyDir("missing");
  fs::remove(dir + "/images.txt");
  ExpectInputError([&] { ReadColmapText(dir); }, {dir + "/images.txt", "cannot open"});
}

TEST(ColmapTextTest, UnwritableNamesAreRefused) {
  ColmapModel m = ReadColmapText(TinyDir("names"));
  const std::string out = TempDir("names_out");
  m.images[0].name = "two\nlines.jpg";
  EXPECT_THROW(WriteColmapText(m, out), std::invalid_argument);
  m.images[0].name = " leading.jpg";
  EXPECT_THROW(WriteColmapText(m, out), std::invalid_argument);
  m.images[0].name = "";
  EXPECT_THROW(WriteColmapText(m, out), std::invalid_argument);
  EXPECT_FALSE(fs::exists(out + "/cameras.txt"));  // nothing written
}

TEST(ColmapTextTest, WritingReplacesExistingFilesAndCreatesDirectories) {
  const ColmapModel m = ReadColmapText(TinyDir("replace"));
  const std::string out = TempDir("replace_out") + "/a/b";
  WriteColmapText(m, out);
  ColmapModel changed = m;
  changed.points3D[0].xyz[2] = 6.5;
  WriteColmapText(changed, out);
  EXPECT_EQ(ReadColmapText(out), changed);
}

}  // namespace
}  // namespace dba
