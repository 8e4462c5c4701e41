// The binary format: exact round trips with BAL, slices, and refusal of
// every kind of corrupt file.
#include "dba/io/binary_problem.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "dba/cluster/partition.h"
#include "dba/cluster/rank_share.h"
#include "dba/common/error.h"
#include "dba/io/bal_reader.h"
#include "dba/io/bal_writer.h"
#include "dba/io/read_problem.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

std::string Tmp(const std::string& name) { return ::testing::TempDir() + "/" + name; }

void ExpectSame(const BalProblem& a, const BalProblem& b) {
  auto bits = [](const auto& x, const auto& y) {
    return x.size() == y.size() &&
           std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
  };
  EXPECT_TRUE(bits(a.cameras, b.cameras));
  EXPECT_TRUE(bits(a.points, b.points));
  EXPECT_TRUE(bits(a.point_offsets, b.point_offsets));
  EXPECT_TRUE(bits(a.obs_camera, b.obs_camera));
  EXPECT_TRUE(bits(a.obs_pixel, b.obs_pixel));
}

std::string ReadBytes(const std::string& path) { return testing::ReadFileBytes(path); }

void WriteBytes(const std::string& path, const std::string& bytes) {
  ASSERT_TRUE(testing::WriteFileBytes(path, bytes)) << path;
}

TEST(BinaryProblem, RoundTripsEverySharedBalProblemExactly) {
  for (const auto& entry : std::filesystem::directory_iterator(DBA_SHARED_DATA_DIR "/bal")) {
    const BalProblem bal = ReadBal(entry.path());
    const std::string bin = Tmp("round.dba"), txt = Tmp("round.txt");
    WriteBinaryProblem(bal, bin);
    EXPECT_TRUE(IsBinaryProblem(bin));
    const BalProblem back = ReadBinaryProblem(bin);
    ExpectSame(bal, back);
    // BAL -> binary -> BAL text -> read: still the same numbers.
    WriteBal(back, txt);
    ExpectSame(bal, ReadProblem(txt));
    EXPECT_EQ(ReadBinaryProblemHeader(bin).num_observations, bal.num_observations());
  }
}

TEST(BinaryProblem, PointsOfAGroupEqualTheExtractedShare) {
  const BalProblem bal = ReadBal(DBA_SHARED_DATA_DIR "/bal/problem-49-7776-pre.txt.bz2");
  const std::string bin = Tmp("share.dba");
  WriteBinaryProblem(bal, bin);
  for (PartitionScheme scheme : {PartitionScheme::kEqual, PartitionScheme::kCameraLocality}) {
    const std::vector<int32_t> group = PartitionPoints(bal, 3, scheme);
    for (int g = 0; g < 3; ++g) {
      std::vector<int64_t> ids;
      const BalProblem slice = ReadBinaryPoints(bin, group, g, &ids);
      const RankShare share = ExtractShare(bal, group, g);
      EXPECT_EQ(ids, share.global_point);
      EXPECT_EQ(slice.points, share.problem.points);
      EXPECT_EQ(slice.point_offsets, share.problem.point_offsets);
      EXPECT_EQ(slice.obs_pixel, share.problem.obs_pixel);
      ASSERT_EQ(slice.obs_camera.size(), share.problem.obs_camera.size());
      for (size_t j = 0; j < slice.obs_camera.size(); ++j) {
        EXPECT_EQ(slice.obs_camera[j], share.global_camera[share.problem.obs_camera[j]]);
      }
    }
  }
}

TEST(BinaryProblem, VisibilityChunksCoverEveryObservationOnce) {
  const BalProblem bal = ReadBal(DBA_SHARED_DATA_DIR "/bal/problem-21-11315-pre.txt.bz2");
  const std::string bin = Tmp("chunks.dba");
  WriteBinaryProblem(bal, bin);
  int64_t next_point = 0, chunks = 0;
  std::vector<int32_t> cameras;
  ForEachVisibilityChunk(bin, 1000, [&](int64_t first, std::span<const int64_t> offsets,
                                        std::span<const int32_t> c) {
    EXPECT_EQ(first, next_point);
    EXPECT_EQ(static_cast<int64_t>(c.size()), offsets.back() - offsets.front());
    next_point += static_cast<int64_t>(offsets.size()) - 1;
    cameras.insert(cameras.end(), c.begin(), c.end());
    ++chunks;
  });
  EXPECT_EQ(next_point, bal.num_points());
  EXPECT_EQ(cameras, bal.obs_camera);
  EXPECT_GT(chunks, 30);
}

class CorruptBinaryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    BalProblem p;
    p.cameras.assign(18, 0.5);
    p.points = {1, 2, 3, 4, 5, 6};
    p.point_offsets = {0, 2, 3};
    p.obs_camera = {0, 1, 1};
    p.obs_pixel = {1, 2, 3, 4, 5, 6};
    WriteBinaryProblem(p, good_);
    bytes_ = ReadBytes(good_);
  }
  // Writes a modified copy and expects the reader to refuse it with `phrase`.
  void ExpectRefused(const std::string& bytes, const std::string& phrase) {
    WriteBytes(bad_, bytes);
    try {
      ReadBinaryProblem(bad_);
      FAIL() << "accepted a file that should contain: " << phrase;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(bad_), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
    }
  }
  std::string good_ = Tmp("good.dba"), bad_ = Tmp("bad.dba");
  std::string bytes_;
};

TEST_F(CorruptBinaryTest, RefusesEachFailureMode) {
  ExpectRefused(bytes_.substr(0, 100), "truncated");
  ExpectRefused(bytes_.substr(0, bytes_.size() - 8), "truncated");
  std::string b = bytes_;
  b[0] = 'X';
  ExpectRefused(b, "bad magic");
  b = bytes_;
  b[8] = 2;  // version 2
  ExpectRefused(b, "version 2");
  b = bytes_;
  std::swap(b[12], b[15]);  // byte-order mark reversed
  ExpectRefused(b, "byte order");
  b = bytes_;
  const BinaryProblemHeader h = ReadBinaryProblemHeader(good_);
  const int32_t bad_camera = 7;
  std::memcpy(b.data() + h.obs_camera_offset + 4, &bad_camera, 4);
  ExpectRefused(b, "camera index 7 of observation 1 is out of range");
  b = bytes_;
  const int64_t bad_offset = 3;  // point 0 would take all observations
  std::memcpy(b.data() + h.point_offsets_offset + 8, &bad_offset, 8);
  ExpectRefused(b, "point offsets");
  b = bytes_;
  const double nan = std::nan("");
  std::memcpy(b.data() + h.obs_pixel_offset, &nan, 8);
  ExpectRefused(b, "non-finite");
}

TEST(BinaryProblem, FailedWriteLeavesNothing) {
  BalProblem p;
  p.cameras.assign(9, 0.0);
  p.points = {0, 0, 0};
  p.point_offsets = {0, 1};
  p.obs_camera = {0};
  p.obs_pixel = {0, 0};
  const std::string dir = Tmp("no_such_dir_bin");
  EXPECT_THROW(WriteBinaryProblem(p, dir + "/x.dba"), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(dir));
}

}  // namespace
}  // namespace dba

namespace dba {
namespace {

// 64-bit sizes (DESIGN.md §5): a header announcing 3 billion observations over
// a sparse file of the matching size (nothing is allocated on disk or in
// memory) is accepted, its section offsets are exact, and reading the
// all-zero offsets fails cleanly instead of overflowing.
TEST(BinaryProblem, CountsPastTwoToThe31) {
  BalProblem p;
  p.cameras.assign(9, 0.0);
  p.points = {0, 0, 0};
  p.point_offsets = {0, 1};
  p.obs_camera = {0};
  p.obs_pixel = {0, 0};
  const std::string path = ::testing::TempDir() + "/huge.dba";
  WriteBinaryProblem(p, path);
  // Rewrite the counts and section table for 3e9 observations of 1e9 points.
  const int64_t cameras = 3000000, points = 1000000000, observations = 3000000000;
  const int64_t cams = 128, pts = cams + 72 * cameras, offs = pts + 24 * points,
                obs_cam = offs + 8 * (points + 1), obs_px = obs_cam + 4 * observations,
                size = obs_px + 16 * observations;
  ASSERT_GT(size, int64_t{1} << 36);  // about 62 GB, all of it a hole
  std::string header = ReadBytes(path).substr(0, 128);
  const uint64_t fields[9] = {static_cast<uint64_t>(cameras), static_cast<uint64_t>(points),
                              static_cast<uint64_t>(observations), static_cast<uint64_t>(cams),
                              static_cast<uint64_t>(pts), static_cast<uint64_t>(offs),
                              static_cast<uint64_t>(obs_cam), static_cast<uint64_t>(obs_px),
                              static_cast<uint64_t>(size)};
  std::memcpy(header.data() + 24, fields, sizeof fields);
  WriteBytes(path, header);
  std::filesystem::resize_file(path, static_cast<uintmax_t>(size));  // sparse
  const BinaryProblemHeader h = ReadBinaryProblemHeader(path);
  EXPECT_EQ(h.num_observations, observations);
  EXPECT_EQ(h.obs_pixel_offset, obs_px);
  EXPECT_EQ(h.file_size, size);
  try {
    ForEachVisibilityChunk(path, 1 << 10, [](int64_t, auto, auto) {});
    FAIL() << "zero offsets accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("point offsets not increasing"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace dba

namespace dba {
namespace {

TEST(BinaryProblem, RewriteWithNewParametersKeepsTheObservations) {
  const BalProblem bal = ReadBal(DBA_SHARED_DATA_DIR "/bal/problem-21-11315-pre.txt.bz2");
  const std::string in = ::testing::TempDir() + "/params_in.dba";
  const std::string out = ::testing::TempDir() + "/params_out.dba";
  WriteBinaryProblem(bal, in);
  std::vector<double> cameras = bal.cameras, points = bal.points;
  for (double& c : cameras) c += 1.0;
  for (double& x : points) x *= 2.0;
  WriteBinaryWithNewParameters(in, out, cameras, points);
  const BalProblem back = ReadBinaryProblem(out);
  EXPECT_EQ(back.cameras, cameras);
  EXPECT_EQ(back.points, points);
  EXPECT_EQ(back.point_offsets, bal.point_offsets);
  EXPECT_EQ(back.obs_camera, bal.obs_camera);
  EXPECT_EQ(back.obs_pixel, bal.obs_pixel);
  points.pop_back();
  EXPECT_THROW(WriteBinaryWithNewParameters(in, out, cameras, points), std::invalid_argument);
}

}  // namespace
}  // namespace dba
