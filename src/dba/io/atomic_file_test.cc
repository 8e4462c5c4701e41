#include "dba/io/atomic_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "dba/testing/temp_files.h"

namespace dba {
namespace {

TEST(AtomicFile, WritesAndReplaces) {
  const std::string path = dba::testing::TempPath("atomic_file_test.txt");
  WriteFileAtomically(path, "first");
  WriteFileAtomically(path, "second\n");
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  EXPECT_EQ(s.str(), "second\n");
}

TEST(AtomicFile, FailureLeavesNothingAndNamesThePath) {
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
