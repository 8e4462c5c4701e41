// Every input the fuzzers (fuzz/run.sh) ever found crashing, hanging or
// exhausting memory, kept in fuzz/regressions/TARGET/, read again the way its
// target reads it: each is read or refused with an exception, never a crash.
// (The fuzzers' own sanitizers and limits are not here: this is the plain
// build's regression check.)
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "dba/io/colmap_binary.h"
#include "dba/io/colmap_text.h"
#include "dba/io/read_problem.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

namespace fs = std::filesystem;

// The part of `bytes` before and after the first `separator` (a separator
// not found: all before).
std::pair<std::string, std::string> Cut(const std::string& bytes, const std::string& separator) {
  const size_t at = bytes.find(separator);
  if (at == std::string::npos) return {bytes, ""};
  return {bytes.substr(0, at), bytes.substr(at + separator.size())};
}

// Reads `input` as fuzz target `target` does.
void ReadAsTarget(const std::string& target, const std::string& input) {
  const std::string bytes = testing::ReadFileBytes(input);
  if (target == "bal_text" || target == "dba_binary") {
    const std::string path = testing::TempPath(target == "bal_text" ? "r.txt" : "r.dba");
    ASSERT_TRUE(testing::WriteFileBytes(path, bytes));
    ReadProblem(path);
    return;
  }
  const bool text = target == "colmap_text";
  const std::string dir = testing::FreshTempDir("regression_" + target);
  const std::string separator = text ? std::string(1, '\0') : std::string("\n--\n");
  const auto [first, rest] = Cut(bytes, separator);
  const auto [second, third] = Cut(rest, separator);
  const std::string ext = text ? ".txt" : ".bin";
  ASSERT_TRUE(testing::WriteFileBytes(dir + "/cameras" + ext, first));
  ASSERT_TRUE(testing::WriteFileBytes(dir + "/images" + ext, second));
  ASSERT_TRUE(testing::WriteFileBytes(dir + "/points3D" + ext, third));
  if (text) {
    ReadColmapText(dir);
  } else {
    ReadColmapBinary(dir);
  }
}

TEST(ReaderRegressions, EveryKeptFuzzInputIsReadOrRefused) {
  const fs::path root = fs::path(DBA_REPO_DATA_DIR).parent_path() / "fuzz" / "regressions";
  ASSERT_TRUE(fs::is_directory(root)) << root;
  int inputs = 0;
  for (const char* target : {"bal_text", "dba_binary", "colmap_text", "colmap_binary"}) {
    if (!fs::is_directory(root / target)) continue;
    for (const auto& entry : fs::directory_iterator(root / target)) {
      if (!entry.is_regular_file() || entry.path().filename() == ".gitkeep") continue;
      ++inputs;
      try {
        ReadAsTarget(target, entry.path().string());
      } catch (const std::exception&) {
        // Refused: fine.
      }
    }
  }
  EXPECT_GT(inputs, 0) << "no regression input under " << root;
}

}  // namespace
}  // namespace dba
