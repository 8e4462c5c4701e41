// AtomicOutputFile: only Commit() makes the file appear; anything else leaves
// no trace. (CommitTogether: tests/cli_solve.sh, a COLMAP output
// under ulimit -f.)
#include "dba/io/atomic_output_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "dba/testing/temp_files.h"

namespace dba {
namespace {

TEST(AtomicOutputFile, CommitRenamesOverThePath) {
  const std::string path = dba::testing::TempPath("tmpfile_commit.txt");
  std::filesystem::remove(path);
  {
    AtomicOutputFile out(path);
    std::fputs("hello", out.file());
    EXPECT_FALSE(std::filesystem::exists(path));  // not before Commit
    out.Commit();
  }
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  EXPECT_EQ(s.str(), "hello");
}

TEST(AtomicOutputFile, WithoutCommitNothingIsLeft) {
  const std::string dir = dba::testing::FreshTempDir("tmpfile_dir");
  try {
    AtomicOutputFile out(dir + "/x.txt");
    std::fputs("partial", out.file());
    out.Fail("simulated failure", 0);
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/x.txt: simulated failure"), std::string::npos);
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(AtomicOutputFile, UncreatableNamesThePath) {
  const std::string path = dba::testing::TempPath("no_such_dir_tmpfile/x.txt");
  try {
    AtomicOutputFile out(path);
    FAIL() << "created a file in a missing directory";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST(AtomicOutputFile, WriteFileAtomicallyReplaces) {
  const std::string path = dba::testing::TempPath("atomic_file_test.txt");
  WriteFileAtomically(path, "first");
  WriteFileAtomically(path, "second\n");
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  EXPECT_EQ(s.str(), "second\n");
}

TEST(AtomicOutputFile, WriteFileAtomicallyFailureLeavesNothing) {
  const std::string dir = dba::testing::TempPath("no_such_dir_atomic");
  const std::string path = dir + "/x.json";
  try {
    WriteFileAtomically(path, "data");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir));
}

}  // namespace
}  // namespace dba
