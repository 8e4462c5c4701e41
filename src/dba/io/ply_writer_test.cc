// Tests of WritePointCloudPly and HeightColour: the file read back byte by
// byte (header text, then 27-byte little-endian records), given colours and
// height colours between the 1st and 99th percentiles, bad arguments, and a
// failed write leaving no file.
#include "dba/io/ply_writer.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "dba/testing/temp_files.h"

namespace dba {
namespace {

namespace fs = std::filesystem;
using Rgb = std::array<uint8_t, 3>;

std::string TempDir(const std::string& name) {
  return dba::testing::FreshTempDir(name);
}

std::string Header(size_t n) {
  return "ply\n"
         "format binary_little_endian 1.0\n"
         "comment written by dba\n"
         "element vertex " +
         std::to_string(n) +
         "\n"
         "property double x\n"
         "property double y\n"
         "property double z\n"
         "property uchar red\n"
         "property uchar green\n"
         "property uchar blue\n"
         "end_header\n";
}

struct Vertex {
  double x, y, z;
  Rgb rgb;
};

// Decodes the records after the header, byte by byte.
std::vector<Vertex> Records(const std::string& bytes, size_t header_size) {
  std::vector<Vertex> out;
  size_t at = header_size;
  auto u8 = [&] { return static_cast<uint8_t>(bytes[at++]); };
  auto f64 = [&] {
    uint64_t bits = 0;
    for (int b = 0; b < 8; ++b) bits |= uint64_t{u8()} << (8 * b);
    return std::bit_cast<double>(bits);
  };
  while (at + 27 <= bytes.size()) {
    Vertex v;
    v.x = f64();
    v.y = f64();
    v.z = f64();
    v.rgb = {u8(), u8(), u8()};
    out.push_back(v);
  }
  EXPECT_EQ(at, bytes.size()) << "trailing bytes";
  return out;
}

TEST(PlyWriterTest, HeightColourRunsFromBlueToRed) {
  EXPECT_EQ(HeightColour(0), (Rgb{0, 0, 255}));
  EXPECT_EQ(HeightColour(0.125), (Rgb{0, 128, 255}));
  EXPECT_EQ(HeightColour(0.25), (Rgb{0, 255, 255}));
  EXPECT_EQ(HeightColour(0.375), (Rgb{0, 255, 128}));
  EXPECT_EQ(HeightColour(0.5), (Rgb{0, 255, 0}));
  EXPECT_EQ(HeightColour(0.75), (Rgb{255, 255, 0}));
  EXPECT_EQ(HeightColour(0.875), (Rgb{255, 128, 0}));
  EXPECT_EQ(HeightColour(1), (Rgb{255, 0, 0}));
  EXPECT_EQ(HeightColour(-3), (Rgb{0, 0, 255}));
  EXPECT_EQ(HeightColour(7), (Rgb{255, 0, 0}));
  EXPECT_EQ(HeightColour(std::numeric_limits<double>::quiet_NaN()), (Rgb{0, 0, 255}));
}

TEST(PlyWriterTest, GivenColoursAreWrittenWithExactCoordinates) {
  const std::string path = TempDir("ply_rgb") + "/cloud.ply";
  const std::vector<double> xyz = {1.5, -2.25, 3e10, 0.1, -0.0, 1e-300, -7, 8, 9};
  const std::vector<uint8_t> rgb = {255, 0, 1, 2, 3, 4, 128, 64, 32};
  WritePointCloudPly(path, xyz, rgb);
  const std::string bytes = dba::testing::ReadFileBytes(path);
  const std::string header = Header(3);
  ASSERT_EQ(bytes.size(), header.size() + 3 * 27);
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  const std::vector<Vertex> v = Records(bytes, header.size());
  ASSERT_EQ(v.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    // Bit for bit (-0.0 stays -0.0).
    EXPECT_EQ(std::bit_cast<uint64_t>(v[k].x), std::bit_cast<uint64_t>(xyz[3 * k]));
    EXPECT_EQ(std::bit_cast<uint64_t>(v[k].y), std::bit_cast<uint64_t>(xyz[3 * k + 1]));
    EXPECT_EQ(std::bit_cast<uint64_t>(v[k].z), std::bit_cast<uint64_t>(xyz[3 * k + 2]));
    EXPECT_EQ(v[k].rgb, (Rgb{rgb[3 * k], rgb[3 * k + 1], rgb[3 * k + 2]}));
  }
  // The first record's bytes: 1.5 = 0x3FF8000000000000, little-endian.
  EXPECT_EQ(bytes.substr(header.size(), 8), std::string("\0\0\0\0\0\0\xF8\x3F", 8));
  for (const auto& e : fs::directory_iterator(fs::path(path).parent_path())) {
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();  // no temporary left
  }
}

TEST(PlyWriterTest, HeightColoursSpanThePercentiles) {
  const std::string path = TempDir("ply_height") + "/cloud.ply";
  // z = 0, 1, 2, 3, 4 (out of order): percentiles 1 and 99 are 0.04 and 3.96.
  const std::vector<double> xyz = {0, 0, 3, 1, 0, 0, 2, 0, 4, 3, 0, 2, 4, 0, 1};
  WritePointCloudPly(path, xyz, {});
  const std::string bytes = dba::testing::ReadFileBytes(path);
  const std::string header = Header(5);
  ASSERT_EQ(bytes.substr(0, header.size()), header);
  const std::vector<Vertex> v = Records(bytes, header.size());
  ASSERT_EQ(v.size(), 5u);
  for (size_t k = 0; k < 5; ++k) {
    EXPECT_EQ(v[k].x, xyz[3 * k]);
    EXPECT_EQ(v[k].z, xyz[3 * k + 2]);
  }
  EXPECT_EQ(v[1].rgb, (Rgb{0, 0, 255}));    // z = 0, the lowest: blue
  EXPECT_EQ(v[2].rgb, (Rgb{255, 0, 0}));    // z = 4, the highest: red
  EXPECT_EQ(v[3].rgb, (Rgb{0, 255, 0}));    // z = 2: t = 1.96 / 3.92 = 0.5, green
  EXPECT_EQ(v[4].rgb, (Rgb{0, 250, 255}));  // z = 1: t = 0.2449, 255 * 0.9796 = 249.8
  EXPECT_EQ(v[0].rgb, (Rgb{255, 250, 0}));  // z = 3: t = 0.7551, just past yellow

  // A flat cloud is green; a non-finite z is blue and does not move the range.
  const std::vector<double> flat = {0, 0, 1, 1, 1, 1, 2, 2, std::nan("")};
  WritePointCloudPly(path, flat, {});
  const std::vector<Vertex> w =
      Records(dba::testing::ReadFileBytes(path), Header(3).size());
  ASSERT_EQ(w.size(), 3u);
  EXPECT_EQ(w[0].rgb, (Rgb{0, 255, 0}));
  EXPECT_EQ(w[1].rgb, (Rgb{0, 255, 0}));
  EXPECT_EQ(w[2].rgb, (Rgb{0, 0, 255}));
  EXPECT_TRUE(std::isnan(w[2].z));

  // No points: just the header.
  WritePointCloudPly(path, {}, {});
  EXPECT_EQ(dba::testing::ReadFileBytes(path), Header(0));
}

TEST(PlyWriterTest, FailuresLeaveNoFile) {
  const std::string dir = TempDir("ply_fail");
  const std::vector<double> xyz = {1, 2, 3};
  const std::string missing = dir + "/missing/cloud.ply";
  try {
    WritePointCloudPly(missing, xyz, {});
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir + "/missing"));
  EXPECT_TRUE(fs::is_empty(dir));

  // Bad arguments: refused before anything is written; an old file stays.
  const std::string path = dir + "/cloud.ply";
  WritePointCloudPly(path, xyz, std::vector<uint8_t>{1, 2, 3});
  const std::string before = dba::testing::ReadFileBytes(path);
  EXPECT_THROW(WritePointCloudPly(path, std::vector<double>{1, 2}, {}), std::invalid_argument);
  EXPECT_THROW(WritePointCloudPly(path, xyz, std::vector<uint8_t>{1, 2}),
               std::invalid_argument);
  EXPECT_EQ(dba::testing::ReadFileBytes(path), before);
  size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1u);
}

}  // namespace
}  // namespace dba
