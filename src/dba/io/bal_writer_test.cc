// Tests of WriteBal: exact read→write→read round trips (plain and bzip2) and
// no file left behind, nor an old file damaged, when a write fails.
#include "dba/io/bal_writer.h"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "dba/io/bal_reader.h"
#include "dba/testing/synthetic_photo.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

namespace fs = std::filesystem;

// A fresh, empty directory for one test, private to the process.
std::string TestDir(const std::string& name) { return dba::testing::FreshTempDir(name); }

std::string Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

template <class T>
void ExpectBitwiseEqual(const std::vector<T>& a, const std::vector<T>& b,
                        const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(T)), 0) << what;
}

void ExpectBitwiseEqual(const Problem& a, const Problem& b) {
  ExpectBitwiseEqual(a.cameras, b.cameras, "cameras");
  ExpectBitwiseEqual(a.points, b.points, "points");
  ExpectBitwiseEqual(a.point_offsets, b.point_offsets, "point_offsets");
  ExpectBitwiseEqual(a.obs_camera, b.obs_camera, "obs_camera");
  ExpectBitwiseEqual(a.obs_pixel, b.obs_pixel, "obs_pixel");
}

// Only `keep` (if any) in `dir`: no temporary left behind.
void ExpectDirHolds(const std::string& dir, const std::string& keep) {
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_EQ(e.path().filename().string(), keep) << "left behind: " << e.path();
  }
}

// One camera, one point, with values that stress exact round trips.
Problem TrickyProblem() {
  Problem p;
  p.cameras = {-0.0,
               std::numeric_limits<double>::denorm_min(),
               std::numeric_limits<double>::min(),
               std::numeric_limits<double>::max(),
               std::numeric_limits<double>::lowest(),
               0.1,
               1.0 / 3.0,
               -1e-300,
               123456789012345678.0};
  p.points = {std::nextafter(1.0, 2.0), -2.5e-7, 4.9406564584124654e-320};
  p.point_offsets = {0, 2};
  p.obs_camera = {0, 0};
  // Pixels as far out as a reader takes (problem/pixel_range.h: 1e7 px) and
  // a negative zero; the extremes of a double are in the cameras above.
  p.obs_pixel = {-332.65, 262.09, 9999999.999999998, -0.0};
  return p;
}

TEST(BalWriterTest, RoundTripOfSharedFilesIsExact) {
  std::string dir = TestDir("roundtrip");
  for (const char* name : {"problem-49-7776-pre.txt.bz2", "problem-16-22106-pre.txt.bz2",
                           "balbianello-5-544-from-bundler.txt.bz2"}) {
    SCOPED_TRACE(name);
    Problem original = ReadBal(std::string(DBA_SHARED_DATA_DIR "/bal/") + name);
    for (const char* ext : {".txt", ".txt.bz2"}) {
      std::string path = dir + "/" + name + ext;
      WriteBal(original, path);
      Problem again = ReadBal(path);
      ExpectBitwiseEqual(original, again);
      // Writing is deterministic: read→write→read→write gives the same bytes.
      std::string path2 = path + ".second" + ext;
      WriteBal(again, path2);
      EXPECT_EQ(Slurp(path), Slurp(path2));
    }
    EXPECT_EQ(Slurp(dir + "/" + name + ".txt.bz2").substr(0, 3), "BZh");
    EXPECT_NE(Slurp(dir + "/" + name + ".txt").substr(0, 3), "BZh");
  }
}

TEST(BalWriterTest, RoundTripOfExtremeValuesIsExact) {
  std::string dir = TestDir("extreme");
  Problem p = TrickyProblem();
  for (const char* name : {"/p.txt", "/p.bz2"}) {
    WriteBal(p, dir + name);
    ExpectBitwiseEqual(p, ReadBal(dir + name));
  }
}

TEST(BalWriterTest, WritesPointMajorBalText) {
  std::string dir = TestDir("text");
  Problem p;
  p.cameras.assign(2 * kBalCameraSize, 0.5);
  p.points = {1, 2, 3, 4, 5, 6};
  p.point_offsets = {0, 1, 3};
  p.obs_camera = {1, 0, 1};
  p.obs_pixel = {1.5, -2, 3, 4, 5, 6};
  WriteBal(p, dir + "/p.txt");
  std::string text = Slurp(dir + "/p.txt");
  EXPECT_EQ(text.substr(0, text.find("0.5")), "2 2 3\n1 0 1.5 -2\n0 1 3 4\n1 1 5 6\n");
  ExpectDirHolds(dir, "p.txt");
}

TEST(BalWriterTest, ReplacesAnExistingFile) {
  std::string dir = TestDir("replace");
  std::string path = dir + "/p.txt";
  std::ofstream(path) << "old contents";
  WriteBal(TrickyProblem(), path);
  ExpectBitwiseEqual(TrickyProblem(), ReadBal(path));
  ExpectDirHolds(dir, "p.txt");
}

TEST(BalWriterTest, MissingDirectoryFailsAndLeavesNoFile) {
  std::string dir = TestDir("missing_dir");
  std::string path = dir + "/no/such/dir/p.txt";
  try {
    WriteBal(TrickyProblem(), path);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir + "/no"));
  ExpectDirHolds(dir, "");
}

// A directory is no output (io/output_target.h): refused before a byte is
// written, and no temporary is made. (A rename that fails after the write:
// atomic_output_file_test.cc.)
TEST(BalWriterTest, DirectoryIsRefusedAndNoTemporaryIsMade) {
  std::string dir = TestDir("rename");
  std::string path = dir + "/target";
  fs::create_directories(path + "/occupied");  // a non-empty directory
  for (const char* suffix : {"", ".bz2"}) {
    if (*suffix) fs::create_directories(path + suffix + "/occupied");
    EXPECT_THROW(WriteBal(TrickyProblem(), path + suffix), std::invalid_argument);
  }
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
  }
}

// Makes writes past `bytes` fail with EFBIG, as a full disk would fail them.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    getrlimit(RLIMIT_FSIZE, &old_);
    rlimit lim = old_;
    lim.rlim_cur = bytes;
    ok_ = setrlimit(RLIMIT_FSIZE, &lim) == 0;
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &old_);
    std::signal(SIGXFSZ, old_handler_);
  }
  bool ok() const { return ok_; }

 private:
  rlimit old_{};
  void (*old_handler_)(int) = nullptr;
  bool ok_ = false;
};

TEST(BalWriterTest, FailedWriteRemovesTheTemporaryAndKeepsTheOldFile) {
  Problem big = ReadBal(DBA_SHARED_DATA_DIR "/bal/problem-49-7776-pre.txt.bz2");
  std::string dir = TestDir("full");
  for (const char* name : {"p.txt", "p.txt.bz2"}) {
    SCOPED_TRACE(name);
    std::string path = dir + "/" + name;
    std::ofstream(path) << "old contents";
    std::string error;
    {
      FileSizeLimit limit(64 * 1024);
      ASSERT_TRUE(limit.ok());
      try {
        WriteBal(big, path);
      } catch (const std::runtime_error& e) {
        error = e.what();
      }
    }
    EXPECT_NE(error.find(path), std::string::npos) << error;
    EXPECT_NE(error.find("File too large"), std::string::npos) << error;
    EXPECT_EQ(Slurp(path), "old contents");
    ExpectDirHolds(dir, name);
    fs::remove(path);
  }
}

TEST(BalWriterTest, RefusesNonFiniteValuesAndInconsistentArrays) {
  std::string dir = TestDir("invalid");
  Problem p = TrickyProblem();
  p.points[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(WriteBal(p, dir + "/nan.txt"), std::invalid_argument);
  p = TrickyProblem();
  p.obs_camera[1] = 1;  // only camera 0 exists
  EXPECT_THROW(WriteBal(p, dir + "/bad_camera.txt"), std::invalid_argument);
  p = TrickyProblem();
  p.point_offsets.back() = 3;
  EXPECT_THROW(WriteBal(p, dir + "/bad_offsets.txt"), std::invalid_argument);
  ExpectDirHolds(dir, "");
}

}  // namespace
}  // namespace dba

namespace dba {
namespace {

// BAL text has no shared intrinsics: a photogrammetric problem is refused
// with a message saying so, and no file (not even a temporary) is left.
TEST(BalWriterTest, RefusesAPhotogrammetricProblem) {
  testing::SyntheticPhotoOptions o;
  o.num_groups = 2;
  const Problem photo = testing::MakeSyntheticPhoto(o).problem;
  const std::string dir = TestDir("photo");
  try {
    WriteBal(photo, dir + "/p.txt");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("cannot hold shared intrinsics"), std::string::npos) << what;
    EXPECT_NE(what.find(".dba"), std::string::npos) << what;
    EXPECT_NE(what.find("2 intrinsic groups"), std::string::npos) << what;
  }
  ExpectDirHolds(dir, "");
}

}  // namespace
}  // namespace dba
