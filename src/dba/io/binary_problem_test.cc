// The binary format: exact round trips with BAL and photogrammetric
// problems, slices, and refusal of every kind of corrupt file.
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
#include "dba/problem/fixings.h"
#include "dba/testing/synthetic_photo.h"
#include "dba/testing/synthetic_rig.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

std::string Tmp(const std::string& name) { return testing::TempPath(name); }

void ExpectSame(const Problem& a, const Problem& b) {
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
    const Problem bal = ReadBal(entry.path());
    const std::string bin = Tmp("round.dba"), txt = Tmp("round.txt");
    WriteBinaryProblem(bal, bin);
    EXPECT_TRUE(IsBinaryProblem(bin));
    const Problem back = ReadBinaryProblem(bin);
    ExpectSame(bal, back);
    // BAL -> binary -> BAL text -> read: still the same numbers.
    WriteBal(back, txt);
    ExpectSame(bal, ReadProblem(txt));
    EXPECT_EQ(ReadBinaryProblemHeader(bin).num_observations, bal.num_observations());
  }
}

TEST(BinaryProblem, PointsOfAGroupEqualTheExtractedShare) {
  const Problem bal = ReadBal(DBA_SHARED_DATA_DIR "/bal/problem-49-7776-pre.txt.bz2");
  const std::string bin = Tmp("share.dba");
  WriteBinaryProblem(bal, bin);
  for (PartitionScheme scheme : {PartitionScheme::kEqual, PartitionScheme::kCameraLocality}) {
    const std::vector<int32_t> group = PartitionPoints(bal, 3, scheme);
    for (int g = 0; g < 3; ++g) {
      std::vector<int64_t> ids;
      const Problem slice = ReadBinaryPoints(bin, group, g, &ids);
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
  const Problem bal = ReadBal(DBA_SHARED_DATA_DIR "/bal/problem-21-11315-pre.txt.bz2");
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
    Problem p;
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
  ExpectRefused(b, "observation 0: pixel (nan, 2) is not finite");
  b = bytes_;
  const double far = -2e7;  // observation 1's y: beyond any image (problem/pixel_range.h)
  std::memcpy(b.data() + h.obs_pixel_offset + 8 * 3, &far, 8);
  ExpectRefused(b, "observation 1: pixel (3, -20000000) is beyond 1e7 px from the origin");
}

// Issue "Nothing lost, nothing wrong", items 7 and 8: counts whose layout
// sums would wrap are refused before any arithmetic; a wrong file-size field
// is named as such; a .dba with a damaged magic is not read as BAL text.
TEST_F(CorruptBinaryTest, HugeCountsAFieldAndTheMagicAreNamedRight) {
  std::string b = bytes_;
  const uint64_t counts[3] = {1, 3 * (uint64_t{1} << 57) + 10, uint64_t{1} << 60};
  std::memcpy(b.data() + 24, counts, sizeof counts);  // RawHeader::counts
  ExpectRefused(b, "need more than the " + std::to_string(bytes_.size()) + " bytes of the file");
  b = bytes_;
  uint64_t file_size = 0;
  std::memcpy(&file_size, b.data() + 88, 8);  // RawHeader::file_size
  file_size += 8;
  std::memcpy(b.data() + 88, &file_size, 8);
  ExpectRefused(b, "the header's file-size field says " + std::to_string(file_size));
  b = bytes_;
  b[2] ^= 0x20;
  WriteBytes(bad_, b);
  try {
    ReadProblem(bad_);
    FAIL() << "a .dba with a damaged magic was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("does not start with the dba binary magic"),
              std::string::npos)
        << e.what();
  }
}

TEST(BinaryProblem, FailedWriteLeavesNothing) {
  Problem p;
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

// 64-bit sizes (docs/design.md §6): a header announcing 3 billion observations over
// a sparse file of the matching size (nothing is allocated on disk or in
// memory) is accepted, its section offsets are exact, and reading the
// all-zero offsets fails cleanly instead of overflowing.
TEST(BinaryProblem, CountsPastTwoToThe31) {
  Problem p;
  p.cameras.assign(9, 0.0);
  p.points = {0, 0, 0};
  p.point_offsets = {0, 1};
  p.obs_camera = {0};
  p.obs_pixel = {0, 0};
  const std::string path = Tmp("huge.dba");
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
  const Problem bal = ReadBal(DBA_SHARED_DATA_DIR "/bal/problem-21-11315-pre.txt.bz2");
  const std::string in = Tmp("params_in.dba");
  const std::string out = Tmp("params_out.dba");
  WriteBinaryProblem(bal, in);
  std::vector<double> cameras = bal.cameras, points = bal.points;
  for (double& c : cameras) c += 1.0;
  for (double& x : points) x *= 2.0;
  Problem side = bal;
  side.cameras = cameras;
  WriteBinaryWithNewParameters(in, out, side, points);
  const Problem back = ReadBinaryProblem(out);
  EXPECT_EQ(back.cameras, cameras);
  EXPECT_EQ(back.points, points);
  EXPECT_EQ(back.point_offsets, bal.point_offsets);
  EXPECT_EQ(back.obs_camera, bal.obs_camera);
  EXPECT_EQ(back.obs_pixel, bal.obs_pixel);
  points.pop_back();
  EXPECT_THROW(WriteBinaryWithNewParameters(in, out, side, points), std::invalid_argument);
}

}  // namespace
}  // namespace dba

// Version 2: the photogrammetric model (poses + shared intrinsic groups) and
// the fixed flags.
namespace dba {
namespace {

// Every array and the model, bit for bit.
void ExpectIdentical(const Problem& a, const Problem& b) {
  EXPECT_EQ(a.model, b.model);
  EXPECT_EQ(a.camera_intrinsics, b.camera_intrinsics);
  EXPECT_EQ(a.fixed_cameras, b.fixed_cameras);
  EXPECT_EQ(a.fixed_intrinsics, b.fixed_intrinsics);
  ExpectSame(a, b);
}

Problem PhotoProblem(int num_groups = 3) {
  testing::SyntheticPhotoOptions o;
  o.geometry.num_cameras = 7;
  o.geometry.num_points = 30;
  o.geometry.pixel_noise = 0.5;
  o.geometry.rotation_perturbation = 0.01;
  o.geometry.point_perturbation = 0.05;
  o.num_groups = num_groups;
  o.focal_perturbation = 0.01;
  o.principal_perturbation = 2.0;
  return testing::MakeSyntheticPhoto(o).problem;
}

TEST(BinaryProblemPhoto, RoundTripIsIdentical) {
  Problem p = PhotoProblem();
  ASSERT_EQ(p.model, CameraModel::kPhoto);
  ASSERT_EQ(p.num_groups(), 3);
  const std::string path = Tmp("photo.dba");
  WriteBinaryProblem(p, path);
  const BinaryProblemHeader h = ReadBinaryProblemHeader(path);
  EXPECT_EQ(h.version, 2u);
  EXPECT_EQ(h.camera_model, 2u);
  EXPECT_EQ(h.camera_size, 6u);
  EXPECT_EQ(h.model, CameraModel::kPhoto);
  EXPECT_EQ(h.num_cameras, 7);
  EXPECT_EQ(h.num_intrinsics, 3);
  EXPECT_FALSE(h.has_fixed_cameras);
  EXPECT_FALSE(h.has_intrinsics_free);
  EXPECT_EQ(h.camera_side_size(), static_cast<int64_t>(p.cameras.size()));
  ExpectIdentical(p, ReadBinaryProblem(path));
  EXPECT_EQ(ReadBinaryCameraSide(path).cameras, p.cameras);  // poses, then intrinsics
  const CameraSide side = ReadBinaryCameraSide(path);
  EXPECT_EQ(side.model, CameraModel::kPhoto);
  EXPECT_EQ(side.cameras, p.cameras);
  EXPECT_EQ(side.camera_intrinsics, p.camera_intrinsics);
  // (a CameraSide: points and observations are not in its type)
  // Writing it again gives the same bytes.
  WriteBinaryProblem(ReadBinaryProblem(path), Tmp("photo2.dba"));
  EXPECT_EQ(ReadBytes(path), ReadBytes(Tmp("photo2.dba")));

  // With fixed flags (each alone and both): still identical, emptiness kept.
  for (int variant = 0; variant < 3; ++variant) {
    Problem q = p;
    if (variant != 1) q.fixed_cameras = {1, 0, 0, 1, 0, 0, 0};
    if (variant != 0) q.fixed_intrinsics = {0, kIntrinsicCx | kIntrinsicCy | kIntrinsicK2, kAllIntrinsics};
    WriteBinaryProblem(q, path);
    const BinaryProblemHeader hq = ReadBinaryProblemHeader(path);
    EXPECT_EQ(hq.has_fixed_cameras, !q.fixed_cameras.empty());
    EXPECT_EQ(hq.has_intrinsics_free, !q.fixed_intrinsics.empty());
    ExpectIdentical(q, ReadBinaryProblem(path));
    const CameraSide s = ReadBinaryCameraSide(path);
    EXPECT_EQ(s.fixed_cameras, q.fixed_cameras);
    EXPECT_EQ(s.fixed_intrinsics, q.fixed_intrinsics);
  }
}

TEST(BinaryProblemPhoto, BalStaysVersion1AndFixedBalCamerasUseVersion2) {
  const Problem bal = ReadBal(DBA_SHARED_DATA_DIR "/bal/problem-49-7776-pre.txt.bz2");
  const std::string path = Tmp("bal_v1.dba");
  WriteBinaryProblem(bal, path);
  EXPECT_EQ(ReadBinaryProblemHeader(path).version, 1u);
  // Version 1 is the format as before: the streaming BAL writer gives the same bytes.
  {
    BinaryProblemWriter w(Tmp("bal_v1_stream.dba"), bal.num_images(), bal.num_points(),
                          bal.num_observations());
    w.WriteCameras(bal.cameras);
    for (int64_t k = 0; k < bal.num_points(); ++k) {
      const int64_t o0 = bal.point_offsets[k], o1 = bal.point_offsets[k + 1];
      w.AppendPoint(bal.point(k), std::span<const int32_t>(bal.obs_camera.data() + o0, o1 - o0),
                    std::span<const double>(bal.obs_pixel.data() + 2 * o0, 2 * (o1 - o0)));
    }
    w.Commit();
  }
  EXPECT_EQ(ReadBytes(path), ReadBytes(Tmp("bal_v1_stream.dba")));
  Problem fixed = bal;
  fixed.fixed_cameras.assign(bal.num_images(), 0);
  fixed.fixed_cameras[3] = 1;
  WriteBinaryProblem(fixed, path);
  const BinaryProblemHeader h = ReadBinaryProblemHeader(path);
  EXPECT_EQ(h.version, 2u);
  EXPECT_EQ(h.model, CameraModel::kBal);
  EXPECT_EQ(h.num_intrinsics, 0);
  EXPECT_TRUE(h.has_fixed_cameras);
  ExpectIdentical(fixed, ReadBinaryProblem(path));
}

TEST(BinaryProblemPhoto, PointsOfAGroupCarryTheWholeCameraSide) {
  Problem p = PhotoProblem();
  p.fixed_cameras = {0, 1, 0, 0, 0, 0, 0};
  p.fixed_intrinsics = {0, kIntrinsicK2, kIntrinsicCx | kIntrinsicCy | kIntrinsicK1 | kIntrinsicK2};
  const std::string path = Tmp("photo_share.dba");
  WriteBinaryProblem(p, path);
  for (PartitionScheme scheme : {PartitionScheme::kEqual, PartitionScheme::kCameraLocality}) {
    const std::vector<int32_t> group = PartitionPoints(p, 3, scheme);
    for (int g = 0; g < 3; ++g) {
      RankShare read;
      read.problem = ReadBinaryPoints(path, group, g, &read.global_point);
      EXPECT_EQ(read.problem.model, CameraModel::kPhoto);
      EXPECT_EQ(read.problem.cameras, p.cameras);
      EXPECT_EQ(read.problem.camera_intrinsics, p.camera_intrinsics);
      EXPECT_EQ(read.problem.fixed_cameras, p.fixed_cameras);
      EXPECT_EQ(read.problem.fixed_intrinsics, p.fixed_intrinsics);
      KeepTouchedCameras(&read);
      const RankShare share = ExtractShare(p, group, g);
      EXPECT_EQ(read.global_point, share.global_point);
      EXPECT_EQ(read.global_camera, share.global_camera);
      EXPECT_EQ(read.global_intrinsics, share.global_intrinsics);
      ExpectIdentical(read.problem, share.problem);
    }
  }
}

TEST(BinaryProblemPhoto, RewriteWithNewParametersKeepsGroupsAndFlags) {
  Problem p = PhotoProblem();
  p.fixed_intrinsics = {0, kIntrinsicCx | kIntrinsicCy | kIntrinsicK1 | kIntrinsicK2, kIntrinsicK1 | kIntrinsicK2};
  const std::string in = Tmp("photo_params_in.dba"), out = Tmp("photo_params_out.dba");
  WriteBinaryProblem(p, in);
  std::vector<double> cameras = p.cameras, points = p.points;
  for (double& c : cameras) c *= 1.5;
  for (double& x : points) x -= 1.0;
  Problem side = p;
  side.cameras = cameras;
  WriteBinaryWithNewParameters(in, out, side, points);
  Problem want = p;
  want.cameras = cameras;
  want.points = points;
  ExpectIdentical(want, ReadBinaryProblem(out));
  side.cameras.pop_back();  // one intrinsic short
  EXPECT_THROW(WriteBinaryWithNewParameters(in, out, side, points), std::invalid_argument);
}

TEST(BinaryProblemPhoto, WriterRefusesAnInconsistentCameraSideAndLeavesNothing) {
  const Problem good = PhotoProblem();
  const std::string path = Tmp("photo_refused.dba");
  std::filesystem::remove(path);
  auto expect_refused = [&](const Problem& p, const std::string& what) {
    EXPECT_THROW(WriteBinaryProblem(p, path), std::invalid_argument) << what;
    EXPECT_FALSE(std::filesystem::exists(path)) << what;
  };
  Problem p = good;
  p.camera_intrinsics[2] = 3;  // only groups 0..2
  expect_refused(p, "group id out of range");
  p = good;
  p.cameras.pop_back();  // not 6 per image + 5 per group
  expect_refused(p, "camera-side size");
  p = good;
  p.fixed_cameras = {0, 1};
  expect_refused(p, "fixed flags of the wrong size");
  p = good;
  p.fixed_intrinsics = {0, 0, 32};
  expect_refused(p, "mask beyond kAllIntrinsics");
  p = good;
  p.cameras.resize(6 * 7);  // no intrinsic group at all
  expect_refused(p, "no groups");
  Problem bal;
  bal.cameras.assign(18, 0.5);
  bal.camera_intrinsics = {0, 0};  // groups in a BAL problem
  bal.points = {1, 2, 3};
  bal.point_offsets = {0, 2};
  bal.obs_camera = {0, 1};
  bal.obs_pixel = {1, 2, 3, 4};
  expect_refused(bal, "BAL with image groups");
}

class CorruptPhotoBinaryTest : public CorruptBinaryTest {
 protected:
  void SetUp() override {
    Problem p = PhotoProblem(2);
    p.fixed_cameras.assign(7, 0);
    p.fixed_cameras[0] = 1;
    p.fixed_intrinsics = {0, kIntrinsicCx | kIntrinsicCy | kIntrinsicK1 | kIntrinsicK2};
    WriteBinaryProblem(p, good_);
    bytes_ = ReadBytes(good_);
    h_ = ReadBinaryProblemHeader(good_);
    ASSERT_EQ(h_.version, 2u);
  }
  template <typename T>
  std::string With(int64_t offset, T value) const {
    std::string b = bytes_;
    std::memcpy(b.data() + offset, &value, sizeof value);
    return b;
  }
  BinaryProblemHeader h_;
};

TEST_F(CorruptPhotoBinaryTest, RefusesEachFailureMode) {
  // The intact file reads.
  EXPECT_EQ(ReadBinaryProblem(good_).num_groups(), 2);
  // Group id out of range, and negative.
  ExpectRefused(With<int32_t>(h_.image_groups_offset + 4 * 3, 2),
                "intrinsic group 2 of image 3 is out of range [0, 2)");
  ExpectRefused(With<int32_t>(h_.image_groups_offset, -1),
                "intrinsic group -1 of image 0 is out of range");
  // Group count inconsistent: none, more than images, and any number that
  // moves the sections away from the table.
  ExpectRefused(With<uint32_t>(96, 0), "intrinsic group count 0 is inconsistent with 7 images");
  ExpectRefused(With<uint32_t>(96, 8), "intrinsic group count 8 is inconsistent with 7 images");
  ExpectRefused(With<uint32_t>(96, 3), "does not match the counts");
  // Truncated sections: the file ends inside the image groups or the flags.
  ExpectRefused(bytes_.substr(0, h_.image_groups_offset + 8), "truncated");
  ExpectRefused(bytes_.substr(0, h_.flags_offset + 3), "truncated");
  // Non-finite intrinsics (group 1's k1) and poses.
  ExpectRefused(With<double>(h_.intrinsics_offset + 8 * (5 + 3), std::nan("")),
                "non-finite value in intrinsics of group 1 (parameter 3)");
  ExpectRefused(With<double>(h_.intrinsics_offset + 8 * 0, INFINITY),
                "non-finite value in intrinsics of group 0 (parameter 0)");
  ExpectRefused(With<double>(h_.cameras_offset + 8, std::nan("")), "non-finite value in cameras");
  // Flags out of range.
  ExpectRefused(With<uint8_t>(h_.flags_offset + 2, 2), "fixed flag 2 of camera 2 is not 0 or 1");
  ExpectRefused(With<uint8_t>(h_.flags_offset + 7 + 1, 64),
                "free-intrinsics mask 64 of group 1 has bits beyond");
  // Header: unknown optional sections, moved section table, wrong model or
  // camera size, a photogrammetric model in a version-1 header.
  ExpectRefused(With<uint32_t>(100, 7), "unknown optional sections 7");
  ExpectRefused(With<uint32_t>(100, 1), "does not match the counts");
  ExpectRefused(With<uint64_t>(112, h_.image_groups_offset + 8), "version 2 header");
  ExpectRefused(With<uint32_t>(20, 9), "camera model 2 of size 9 is not supported");
  ExpectRefused(With<uint32_t>(16, 3), "camera model 3 of size 6 is not supported");
  ExpectRefused(With<uint32_t>(8, 1), "camera model 2 of size 6 is not supported in version 1");
  ExpectRefused(With<uint32_t>(8, 5), "format version 5, this dba reads versions 1 to 4");
  // A BAL model with free-intrinsics masks, or with intrinsic groups.
  std::string b = With<uint32_t>(16, 1);
  const uint32_t nine = 9, fixed_only = 1;
  std::memcpy(b.data() + 20, &nine, 4);
  ExpectRefused(b, "unknown optional sections 3 for camera model 1");
  std::memcpy(b.data() + 100, &fixed_only, 4);
  ExpectRefused(b, "intrinsic group count 2 is inconsistent with 7 BAL cameras");
}

TEST_F(CorruptPhotoBinaryTest, EveryReaderRefusesABadGroup) {
  WriteBytes(bad_, With<int32_t>(h_.image_groups_offset + 4 * 6, 5));
  EXPECT_THROW(ReadBinaryCameraSide(bad_), InputError);
  std::vector<int64_t> ids;
  const std::vector<int32_t> all(h_.num_points, 0);
  EXPECT_THROW(ReadBinaryPoints(bad_, all, 0, &ids), InputError);
  Problem side;  // the camera side the file's header promises
  side.model = CameraModel::kPhoto;
  side.camera_intrinsics.assign(h_.num_cameras, 0);
  side.cameras.resize(h_.camera_side_size());
  EXPECT_THROW(WriteBinaryWithNewParameters(bad_, Tmp("never.dba"), side,
                                            std::vector<double>(3 * h_.num_points)),
               InputError);
  EXPECT_FALSE(std::filesystem::exists(Tmp("never.dba")));
}

TEST_F(CorruptBinaryTest, Version1RelabelledAsVersion2OrAnUnknownVersionIsRefused) {
  std::string b = bytes_;
  b[8] = 5;
  ExpectRefused(b, "format version 5");
  b[8] = 4;  // version 4's frames are 8 bytes of the cameras here
  ExpectRefused(b, "version 4 header:");
  b[8] = 3;  // version 3 is photogrammetric only
  ExpectRefused(b, "version 3 header: 0 intrinsic slots");
  b[8] = 2;  // the version-2 section table is zero
  ExpectRefused(b, "version 2 header: intrinsics, image groups and flags sections do not match");
}

}  // namespace
}  // namespace dba

namespace dba {
namespace {

// Files written by earlier versions of the writer, checked in
// (tests/data): a version-1 BAL file and a version-2 photogrammetric one
// with a fixed image and fixed intrinsics read back to these exact values,
// so a layout change that breaks old files fails here.
TEST(CheckedInBinaryFiles, Version1BalDecodes) {
  const Problem p = ReadBinaryProblem(DBA_TEST_DATA_DIR "/v1_bal.dba");
  EXPECT_EQ(ReadBinaryProblemHeader(DBA_TEST_DATA_DIR "/v1_bal.dba").version, 1u);
  EXPECT_EQ(p.model, CameraModel::kBal);
  EXPECT_EQ(p.cameras, (std::vector<double>{0.1, -0.2, 0.3, 1, 2, -10, 500, -1e-3, 2e-6, -0.05,
                                            0.01, 0.02, -1.5, 0.5, -9, 510, 1e-3, -3e-6}));
  EXPECT_EQ(p.points, (std::vector<double>{0.25, -0.5, 1.0, -1.25, 0.75, 2.5}));
  EXPECT_EQ(p.point_offsets, (std::vector<int64_t>{0, 2, 3}));
  EXPECT_EQ(p.obs_camera, (std::vector<int32_t>{0, 1, 1}));
  EXPECT_EQ(p.obs_pixel, (std::vector<double>{10.5, -20.25, 11.0, -19.5, -30.125, 40.0625}));
  EXPECT_TRUE(p.fixed_cameras.empty());
}

TEST(CheckedInBinaryFiles, Version2PhotoWithFixingsDecodes) {
  const Problem p = ReadBinaryProblem(DBA_TEST_DATA_DIR "/v2_photo_fixings.dba");
  EXPECT_EQ(ReadBinaryProblemHeader(DBA_TEST_DATA_DIR "/v2_photo_fixings.dba").version, 2u);
  EXPECT_EQ(p.model, CameraModel::kPhoto);
  EXPECT_EQ(p.num_images(), 3);
  EXPECT_EQ(p.num_groups(), 2);
  EXPECT_EQ(p.cameras,
            (std::vector<double>{0.01, 0.02, 0.03, 1, 2, 3, -0.01, 0.0, 0.02, 4, 5, 6, 0, 0.1, 0,
                                 7, 8, 9, 800, 320, 240, 0.01, -0.001, 900, 330, 250, -0.02,
                                 0.002}));
  EXPECT_EQ(p.camera_intrinsics, (std::vector<int32_t>{0, 1, 0}));
  EXPECT_EQ(p.fixed_cameras, (std::vector<uint8_t>{0, 1, 0}));
  EXPECT_EQ(p.fixed_intrinsics, (std::vector<uint16_t>{0, kIntrinsicCx | kIntrinsicCy}));
  EXPECT_EQ(p.points, (std::vector<double>{0.5, 0.25, 10, -0.5, 1.5, 12}));
  EXPECT_EQ(p.point_offsets, (std::vector<int64_t>{0, 2, 4}));
  EXPECT_EQ(p.obs_camera, (std::vector<int32_t>{0, 2, 1, 2}));
  EXPECT_EQ(p.obs_pixel,
            (std::vector<double>{300.5, 200.25, 310, 210.5, 280.75, 260, 290.125, 250.5}));
}

}  // namespace
}  // namespace dba

namespace dba {
namespace {

// Version 3: groups of different lens models and sizes, fixed by name,
// round-trip exactly; a problem of RADIAL groups is still version 2; a
// model id, a parameter count or a mask that does not fit is refused.
Problem MixedLensProblem() {
  testing::SyntheticPhotoOptions o;
  o.geometry.num_cameras = 6;
  o.geometry.num_points = 40;
  o.num_groups = 3;
  o.lens_model = LensModel::kRadTanThinPrismFisheye;
  Problem p = testing::MakeSyntheticPhoto(o).problem;
  p.group_models = {LensModel::kFisheye, LensModel::kThinPrismFisheye,
                    LensModel::kRadTanThinPrismFisheye};
  ApplyFixings(Fixings{{1}, {{2, {"k5", "s3"}}, {0, {"cx", "cy"}}}}, &p);
  return p;
}

TEST(BinaryProblem, Version3HoldsEachGroupsLensModel) {
  const Problem p = MixedLensProblem();
  const std::string path = Tmp("v3.dba");
  WriteBinaryProblem(p, path);
  EXPECT_EQ(ReadBinaryProblemHeader(path).version, 3u);
  EXPECT_EQ(ReadBinaryProblemHeader(path).intrinsics_size, 16);
  const Problem q = ReadBinaryProblem(path);
  EXPECT_EQ(q.group_models, p.group_models);
  EXPECT_EQ(q.intrinsics_size, 16);
  EXPECT_EQ(q.cameras, p.cameras);
  EXPECT_EQ(q.camera_intrinsics, p.camera_intrinsics);
  EXPECT_EQ(q.fixed_cameras, p.fixed_cameras);
  EXPECT_EQ(q.fixed_intrinsics, p.fixed_intrinsics);
  EXPECT_EQ(q.fixed_intrinsics[2], (1u << 9) | (1u << 15));  // k5, s3
  EXPECT_EQ(q.obs_pixel, p.obs_pixel);
  // And the ranks' reader sees the same camera side.
  const CameraSide side = ReadBinaryCameraSide(path);
  EXPECT_EQ(side.group_models, p.group_models);
  EXPECT_EQ(side.fixed_intrinsics, p.fixed_intrinsics);

  // RADIAL groups in 5 slots: version 2, as before.
  testing::SyntheticPhotoOptions radial;
  radial.geometry.num_cameras = 6;
  radial.geometry.num_points = 40;
  WriteBinaryProblem(testing::MakeSyntheticPhoto(radial).problem, Tmp("v2.dba"));
  EXPECT_EQ(ReadBinaryProblemHeader(Tmp("v2.dba")).version, 2u);
}

TEST(BinaryProblem, Version3RefusesModelsCountsAndMasksThatDoNotFit) {
  const std::string good = Tmp("v3_good.dba"), bad = Tmp("v3_bad.dba");
  WriteBinaryProblem(MixedLensProblem(), good);
  const BinaryProblemHeader h = ReadBinaryProblemHeader(good);
  const std::string bytes = testing::ReadFileBytes(good);
  auto refused = [&](int64_t at, uint8_t value, const std::string& phrase) {
    std::string b = bytes;
    b[at] = static_cast<char>(value);
    ASSERT_TRUE(testing::WriteFileBytes(bad, b));
    try {
      ReadBinaryProblem(bad);
      ADD_FAILURE() << "accepted: " << phrase;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
    }
  };
  refused(h.group_models_offset, 99, "intrinsic group 0: unknown lens model id 99");
  refused(h.group_models_offset + 1, 5, "FISHEYE has 4 parameters, the file says 5");
  // Group 0 (FISHEYE, 4 parameters): a free bit for parameter 7.
  const int64_t masks = h.flags_offset + h.num_cameras;
  refused(masks, 0x80, "has bits beyond its FISHEYE model's parameters (fx, fy, cx, cy)");

  // The writer refuses a mask beyond the model's parameters, and a model
  // with more parameters than slots.
  Problem p = MixedLensProblem();
  p.fixed_intrinsics[0] = 1u << 6;
  EXPECT_THROW(WriteBinaryProblem(p, Tmp("never.dba")), std::invalid_argument);
  p = MixedLensProblem();
  p.group_models[0] = LensModel::kBrown;
  p.intrinsics_size = 16;
  p.fixed_intrinsics.clear();
  WriteBinaryProblem(p, Tmp("brown.dba"));  // 10 parameters in 16 slots: fine
  EXPECT_EQ(ReadBinaryProblem(Tmp("brown.dba")).group_models[0], LensModel::kBrown);
  EXPECT_FALSE(std::filesystem::exists(Tmp("never.dba")));
}

// Values no camera has (problem/lens_ranges.h) are refused by every reader,
// naming the group, the parameter and the value.
TEST(BinaryProblem, ParametersOutOfTheirLensRangeAreRefused) {
  Problem p = MixedLensProblem();
  p.intrinsics(1)[1] = 0.0;  // THIN_PRISM_FISHEYE's fy
  const std::string path = Tmp("zero_fy.dba");
  WriteBinaryProblem(p, path);
  const std::string phrase = "intrinsic group 1: THIN_PRISM_FISHEYE's fy is 0: it must be > 0";
  for (int reader = 0; reader < 2; ++reader) {
    try {
      if (reader == 0) ReadBinaryProblem(path);
      else ReadBinaryCameraSide(path);
      ADD_FAILURE() << "accepted by reader " << reader;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
    }
  }
}

// Version 4: rigs round-trip exactly; a model without them is written as
// before (version 2 or 3); a rig section that does not fit is refused.
TEST(BinaryProblemRigs, Version4RoundTripsFramesSensorsAndKinds) {
  testing::SyntheticRigOptions o;
  o.sensors = 3;
  o.missing = true;
  Problem p = testing::MakeSyntheticRig(o).problem;
  p.sensor_kind[2] = kSensorHeld;
  const std::string path = Tmp("rig.dba");
  WriteBinaryProblem(p, path);
  const BinaryProblemHeader h = ReadBinaryProblemHeader(path);
  EXPECT_EQ(h.version, 4u);
  EXPECT_EQ(h.num_frames, 6);
  EXPECT_EQ(h.camera_side_size(), static_cast<int64_t>(p.cameras.size()));
  const Problem q = ReadBinaryProblem(path);
  ExpectIdentical(p, q);
  EXPECT_EQ(q.image_frame, p.image_frame);
  EXPECT_EQ(q.sensor_kind, p.sensor_kind);
  WriteBinaryProblem(q, Tmp("rig2.dba"));
  EXPECT_EQ(ReadBytes(path), ReadBytes(Tmp("rig2.dba")));
  // Without the rigs: version 2, the images' poses kept.
  Problem dropped = p;
  dropped.DropRigs();
  WriteBinaryProblem(dropped, Tmp("norig.dba"));
  EXPECT_EQ(ReadBinaryProblemHeader(Tmp("norig.dba")).version, 2u);
  EXPECT_EQ(ReadBinaryProblem(Tmp("norig.dba")).cameras,
            std::vector<double>(p.cameras.begin(), p.cameras.begin() + p.frames_offset()));
}

TEST(BinaryProblemRigs, RefusesFramesAndKindsThatDoNotFit) {
  testing::SyntheticRigOptions o;
  const Problem p = testing::MakeSyntheticRig(o).problem;
  const std::string good = Tmp("rig-good.dba"), bad = Tmp("rig-bad.dba");
  WriteBinaryProblem(p, good);
  const BinaryProblemHeader h = ReadBinaryProblemHeader(good);
  const std::string bytes = ReadBytes(good);
  auto expect_refused = [&](std::string b, const std::string& phrase) {
    WriteBytes(bad, b);
    try {
      ReadBinaryProblem(bad);
      FAIL() << "accepted: " << phrase;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(phrase), std::string::npos) << e.what();
    }
  };
  std::string b = bytes;
  const int32_t frame = 99;
  std::memcpy(&b[h.rig_offset], &frame, 4);
  expect_refused(b, "frame 99 of image 0 is out of range");
  b = bytes;
  b[h.rig_offset + 4 * h.num_cameras + 1] = 7;
  expect_refused(b, "sensor kind 7 of group 1");
  b = bytes;
  b[h.rig_offset + 4 * h.num_cameras + 1] = 0;  // a sensor with a pose called the origin
  expect_refused(b, "is its rig's origin but its sensor pose is not zero");
  b = bytes;
  const int32_t first_frame = 0;  // image 2, sensor 0 of frame 1, into frame 0
  std::memcpy(&b[h.rig_offset + 8], &first_frame, 4);
  expect_refused(b, "frame 0: images 0 and 2 are both of sensor (group) 0 (a frame is one exposure");
  b = bytes;
  const uint64_t frames = 1000;
  std::memcpy(&b[128], &frames, 8);
  expect_refused(b, "frames for");
}

}  // namespace
}  // namespace dba
