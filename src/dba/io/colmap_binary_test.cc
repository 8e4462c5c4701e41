// Tests of the COLMAP binary reader and writer: read -> write reproduces every
// shared binary model byte for byte, binary -> text -> binary too, text models
// survive text -> binary -> text, and damaged files are refused with the file
// and byte offset.
#include "dba/testing/temp_files.h"
#include "dba/io/colmap_binary.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "dba/common/error.h"
#include "dba/io/colmap_text.h"

namespace dba {
namespace {

namespace fs = std::filesystem;

const char* const kBinaryModels[] = {"statue_of_liberty", "fountain_p11", "softmurata_177img"};
const char* const kTextModels[] = {"statue_of_liberty_small_txt", "mithunnallana_6img"};
const char* const kFiles[] = {"cameras.bin", "images.bin", "points3D.bin"};

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

// Index of the first differing byte, or -1 when equal.
int64_t FirstDifferentByte(const std::string& a, const std::string& b) {
  const size_t n = std::min(a.size(), b.size());
  for (size_t i = 0; i < n; ++i) {
    if (a[i] != b[i]) return static_cast<int64_t>(i);
  }
  return a.size() == b.size() ? -1 : static_cast<int64_t>(n);
}

void ExpectSameFiles(const std::string& dir_a, const std::string& dir_b) {
  for (const char* f : kFiles) {
    const std::string a = ReadBytes(dir_a + "/" + f);
    const std::string b = ReadBytes(dir_b + "/" + f);
    EXPECT_EQ(a.size(), b.size()) << f;
    EXPECT_EQ(FirstDifferentByte(a, b), -1) << f;
  }
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
    EXPECT_EQ(e.line(), 0);
    return msg;
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

// A copy of a shared binary model whose `file` is replaced by `bytes`.
std::string DamagedCopy(const std::string& name, const char* folder, const char* file,
                        const std::string& bytes) {
  const std::string dir = TempDir(name);
  for (const char* f : kFiles) {
    fs::copy_file(SharedDir(folder) + "/" + f, dir + "/" + f);
    fs::permissions(dir + "/" + f, fs::perms::owner_read | fs::perms::owner_write);
  }
  WriteBytes(dir + "/" + file, bytes);
  return dir;
}

TEST(ColmapBinaryTest, RoundTripIsByteIdenticalOnEverySharedBinaryModel) {
  for (const char* folder : kBinaryModels) {
    SCOPED_TRACE(folder);
    const ColmapModel original = ReadColmapBinary(SharedDir(folder));
    const std::string dir = TempDir(std::string("round_") + folder);
    WriteColmapBinary(original, dir);
    ExpectSameFiles(SharedDir(folder), dir);
    const ColmapModel reread = ReadColmapBinary(dir);
    EXPECT_EQ(FirstColmapModelDifference(original, reread), "");
    for (const auto& e : fs::directory_iterator(dir)) {
      EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
    }
  }
}

TEST(ColmapBinaryTest, BinaryToTextToBinaryIsByteIdentical) {
  for (const char* folder : kBinaryModels) {
    SCOPED_TRACE(folder);
    const std::string text = TempDir(std::string("b2t_") + folder);
    WriteColmapText(ReadColmapBinary(SharedDir(folder)), text);
    const std::string bin = TempDir(std::string("b2t2b_") + folder);
    WriteColmapBinary(ReadColmapText(text), bin);
    ExpectSameFiles(SharedDir(folder), bin);
  }
}

TEST(ColmapBinaryTest, TextModelsSurviveTextToBinaryToText) {
  for (const char* folder : kTextModels) {
    SCOPED_TRACE(folder);
    const ColmapModel original = ReadColmapText(SharedDir(folder));
    const std::string bin = TempDir(std::string("t2b_") + folder);
    WriteColmapBinary(original, bin);
    const ColmapModel from_bin = ReadColmapBinary(bin);
    EXPECT_EQ(FirstColmapModelDifference(original, from_bin), "");
    // And binary -> binary is stable.
    const std::string bin2 = TempDir(std::string("t2b2b_") + folder);
    WriteColmapBinary(from_bin, bin2);
    ExpectSameFiles(bin, bin2);
    const std::string text = TempDir(std::string("t2b2t_") + folder);
    WriteColmapText(from_bin, text);
    EXPECT_EQ(FirstColmapModelDifference(original, ReadColmapText(text)), "");
  }
}

TEST(ColmapBinaryTest, LayoutOfTheSmallestFile) {
  // statue_of_liberty/cameras.bin: one SIMPLE_RADIAL camera, 64 bytes.
  const ColmapModel m = ReadColmapBinary(SharedDir("statue_of_liberty"));
  ASSERT_EQ(m.cameras.size(), 1u);
  const ColmapCamera& c = m.cameras[0];
  EXPECT_EQ(c.camera_id, 1u);
  EXPECT_EQ(c.ModelName(), "SIMPLE_RADIAL");
  EXPECT_EQ(c.width, 800u);
  EXPECT_EQ(c.height, 1200u);
  EXPECT_EQ(c.params[1], 400.0);
  EXPECT_EQ(c.params[2], 600.0);
  EXPECT_EQ(ReadBytes(SharedDir("statue_of_liberty") + "/cameras.bin").size(), 64u);
  EXPECT_EQ(m.images[0].name, "14522296402_8ba47a6b27_o.jpg");
}

TEST(ColmapBinaryTest, NamesWithBlanksAndEmptyImagesRoundTrip) {
  ColmapModel m = ReadColmapBinary(SharedDir("statue_of_liberty"));
  m.images[0].name = "  a name with blanks\t";
  const std::string dir = TempDir("names");
  WriteColmapBinary(m, dir);
  EXPECT_EQ(ReadColmapBinary(dir).images[0].name, m.images[0].name);
  m.images[0].name = std::string("nul\0inside", 10);
  EXPECT_THROW(WriteColmapBinary(m, dir), std::invalid_argument);
}

TEST(ColmapBinaryTest, TruncatedFilesAreRefused) {
  const std::string images = ReadBytes(SharedDir("fountain_p11") + "/images.bin");
  const std::string points = ReadBytes(SharedDir("fountain_p11") + "/points3D.bin");
  const std::string cameras = ReadBytes(SharedDir("fountain_p11") + "/cameras.bin");

  // The last image's 2D points run past the end: refused when its count is read.
  std::string dir = DamagedCopy("trunc_images", "fountain_p11", "images.bin",
                                images.substr(0, images.size() - 5));
  ExpectInputError([&] { ReadColmapBinary(dir); },
                   {dir + "/images.bin", "at byte ", "image #10", "number of 2D points",
                    "truncated"});

  dir = DamagedCopy("trunc_points", "fountain_p11", "points3D.bin",
                    points.substr(0, points.size() / 2));
  ExpectInputError([&] { ReadColmapBinary(dir); },
                   {dir + "/points3D.bin", "at byte", "truncated"});

  // 11 cameras of 56 bytes after the count; cut inside the last one's params.
  ASSERT_EQ(cameras.size(), 8u + 11 * 56);
  dir = DamagedCopy("trunc_cameras", "fountain_p11", "cameras.bin", cameras.substr(0, 600));
  ExpectInputError([&] { ReadColmapBinary(dir); },
                   {dir + "/cameras.bin", "at byte 592: file truncated", "camera #10",
                    "SIMPLE_RADIAL parameters (f, cx, cy, k) needs 32 bytes, only 8 left"});

  dir = DamagedCopy("empty", "fountain_p11", "cameras.bin", "");
  ExpectInputError([&] { ReadColmapBinary(dir); },
                   {"at byte 0", "the number of cameras needs 8 bytes, only 0 left"});

  // One image whose name runs into the end of the file.
  std::string one = images.substr(0, 8 + 4 + 56 + 4) + std::string(20, 'x');
  const uint64_t count = 1;
  std::memcpy(one.data(), &count, 8);
  dir = DamagedCopy("trunc_name", "fountain_p11", "images.bin", one);
  ExpectInputError([&] { ReadColmapBinary(dir); },
                   {"at byte 92", "image #0 (id 1) name has no terminating NUL byte"});
}

TEST(ColmapBinaryTest, CorruptFilesAreRefused) {
  const std::string images = ReadBytes(SharedDir("fountain_p11") + "/images.bin");
  const std::string cameras = ReadBytes(SharedDir("fountain_p11") + "/cameras.bin");

  // A huge count is refused before anything is allocated.
  std::string bad = images;
  const uint64_t huge = uint64_t{1} << 60;
  std::memcpy(bad.data(), &huge, 8);
  std::string dir = DamagedCopy("huge", "fountain_p11", "images.bin", bad);
  ExpectInputError([&] { ReadColmapBinary(dir); },
                   {"at byte 0", "the number of images is 1152921504606846976",
                    "truncated or corrupt"});

  // Trailing bytes.
  dir = DamagedCopy("trailing", "fountain_p11", "cameras.bin", cameras + "xyz");
  ExpectInputError([&] { ReadColmapBinary(dir); },
                   {"at byte " + std::to_string(cameras.size()),
                    "3 unexpected bytes after the last camera"});

  // Unknown camera model id (first camera's model_id at byte 12).
  bad = cameras;
  const int32_t model = 77;
  std::memcpy(bad.data() + 12, &model, 4);
  dir = DamagedCopy("model", "fountain_p11", "cameras.bin", bad);
  ExpectInputError([&] { ReadColmapBinary(dir); },
                   {"at byte 12", "camera #0 (id 1)", "unknown camera model id 77"});

  // A NaN coordinate (first image's tx at byte 8 + 4 + 32).
  bad = images;
  const double nan = std::nan("");
  std::memcpy(bad.data() + 44, &nan, 8);
  dir = DamagedCopy("nan", "fountain_p11", "images.bin", bad);
  ExpectInputError([&] { ReadColmapBinary(dir); },
                   {dir + "/images.bin", "image #0 (id 1)", "non-finite qvec or tvec"});

  // A track element that does not point back: swap two point3D records' ids.
  const ColmapModel m = ReadColmapBinary(SharedDir("fountain_p11"));
  ColmapModel swapped = m;
  std::swap(swapped.points3D[0].point3D_id, swapped.points3D[1].point3D_id);
  dir = TempDir("swapped");
  WriteColmapBinary(swapped, dir);
  ExpectInputError([&] { ReadColmapBinary(dir); },
                   {dir + "/points3D.bin", "point3D #0", "not back to this point"});
}

}  // namespace
}  // namespace dba
