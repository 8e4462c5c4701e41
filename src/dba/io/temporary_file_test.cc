// TemporaryFile: only Commit() makes the file appear; anything else leaves
// no trace.
#include "dba/io/temporary_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "dba/testing/temp_files.h"

namespace dba {
namespace {

TEST(TemporaryFile, CommitRenamesOverThePath) {
  const std::string path = dba::testing::TempPath("tmpfile_commit.txt");
  std::filesystem::remove(path);
  {
    TemporaryFile out(path);
    std::fputs("hello", out.file());
    EXPECT_FALSE(std::filesystem::exists(path));  // not before Commit
    out.Commit();
  }
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  EXPECT_EQ(s.str(), "hello");
}

TEST(TemporaryFile, WithoutCommitNothingIsLeft) {
  const std::string dir = dba::testing::FreshTempDir("tmpfile_dir");
  try {
    TemporaryFile out(dir + "/x.txt");
    std::fputs("partial", out.file());
    out.Fail("simulated failure", 0);
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/x.txt: simulated failure"), std::string::npos);
  }
  EXPECT_TRUE(std::filesystem::is_empty(dir));
}

TEST(TemporaryFile, UncreatableNamesThePath) {
  const std::string path = dba::testing::TempPath("no_such_dir_tmpfile/x.txt");
  try {
    TemporaryFile out(path);
    FAIL() << "created a file in a missing directory";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dba
