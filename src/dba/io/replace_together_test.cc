// Files replaced together stay together across a SIGKILL at any step
// (io/replace_together.h): the next touch of any one of them leaves all old
// or all new, and nothing of the replacement behind.
#include "dba/io/replace_together.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "dba/io/stale_temporaries.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

namespace fs = std::filesystem;
using dba::testing::FreshTempDir;
using dba::testing::ReadFileBytes;
using dba::testing::WriteFileBytes;

std::vector<std::string> Names(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// Three files, two in one directory (one of them new), one in another; a
// child process replaces them and is killed after step `step`; then one of
// them (a different one each time) is touched: all old or all new. Then
// the first is touched (the journal is beside it): nothing else is left.
// (After the commit, a file whose own old copy and link were removed leads
// nowhere; the others' are removed when they, or the first, are touched.)
TEST(ReplaceTogether, AKillAtAnyStepLeavesAllOldOrAllNew) {
  constexpr int kFiles = 3, kSteps = 2 * kFiles + 2;
  for (int step = 1; step <= kSteps; ++step) {
    const std::string dir = FreshTempDir("kill_at_" + std::to_string(step));
    fs::create_directories(dir + "/a");
    fs::create_directories(dir + "/b");
    const std::vector<std::string> files = {dir + "/a/x.txt", dir + "/a/y.txt", dir + "/b/z.txt"};
    WriteFileBytes(files[0], "old x");
    WriteFileBytes(files[2], "old z");
    const pid_t child = ::fork();
    if (child == 0) {
      ::setenv("DBA_KILL_IN_COMMIT", std::to_string(step).c_str(), 1);
      std::vector<Replacement> r;
      for (const std::string& f : files) {
        r.push_back({TemporaryName(f), f});
        WriteFileBytes(r.back().tmp, "new " + f.substr(f.size() - 5, 1));
      }
      ReplaceTogether(r);
      ::_exit(0);  // not killed
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << "step " << step;
    RecoverStaleTemporaries(files[step % kFiles]);
    const bool committed = step >= kFiles + 2;
    SCOPED_TRACE("killed after step " + std::to_string(step));
    if (committed) {
      EXPECT_EQ(ReadFileBytes(files[0]), "new x");
      EXPECT_EQ(ReadFileBytes(files[1]), "new y");
      EXPECT_EQ(ReadFileBytes(files[2]), "new z");
    } else {
      EXPECT_EQ(ReadFileBytes(files[0]), "old x");
      EXPECT_FALSE(fs::exists(files[1]));
      EXPECT_EQ(ReadFileBytes(files[2]), "old z");
      EXPECT_EQ(Names(dir + "/a"), (std::vector<std::string>{"x.txt"}));  // undone whole
      EXPECT_EQ(Names(dir + "/b"), (std::vector<std::string>{"z.txt"}));
    }
    RecoverStaleTemporaries(files[0]);
    const std::vector<std::string> in_a =
        committed ? std::vector<std::string>{"x.txt", "y.txt"} : std::vector<std::string>{"x.txt"};
    EXPECT_EQ(Names(dir + "/a"), in_a);
    EXPECT_EQ(Names(dir + "/b"), (std::vector<std::string>{"z.txt"}));
  }
}

}  // namespace
}  // namespace dba
