// The per-process scratch directory of the tests (testing/temp_files.h).
#include "dba/testing/temp_files.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace dba {
namespace {

namespace fs = std::filesystem;

TEST(TempFiles, OneFreshDirectoryPerProcessUnderTmpdir) {
  const std::string& dir = testing::TestTempDir();
  EXPECT_EQ(&dir, &testing::TestTempDir());  // made once
  EXPECT_TRUE(fs::is_directory(dir));
  EXPECT_EQ(fs::path(dir).filename().string().rfind("dba_test.", 0), 0u) << dir;
  const char* env = std::getenv("TMPDIR");
  const fs::path base = env != nullptr && *env != '\0' ? env : "/tmp";
  EXPECT_TRUE(fs::equivalent(fs::path(dir).parent_path(), base)) << dir;
  EXPECT_EQ(testing::TempPath("a/b.txt"), dir + "/a/b.txt");
}

TEST(TempFiles, FreshTempDirIsEmptyEveryTime) {
  const std::string dir = testing::FreshTempDir("fresh");
  EXPECT_EQ(dir, testing::TempPath("fresh"));
  ASSERT_TRUE(testing::WriteFileBytes(dir + "/x", "bytes"));
  EXPECT_EQ(testing::ReadFileBytes(dir + "/x"), "bytes");
  EXPECT_EQ(testing::FreshTempDir("fresh"), dir);
  EXPECT_TRUE(fs::is_empty(dir));
}

// A forked child that exits normally runs the static destructors too: it must
// not remove its parent's directory.
TEST(TempFiles, AForkedChildLeavesTheDirectory) {
  const std::string dir = testing::TestTempDir();
  std::fflush(nullptr);  // nothing buffered is written twice
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) std::exit(0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status));
  EXPECT_TRUE(fs::is_directory(dir));
}

}  // namespace
}  // namespace dba
