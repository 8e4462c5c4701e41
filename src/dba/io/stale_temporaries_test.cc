// What a killed writer left is put right, and nothing of a live one is
// touched (io/stale_temporaries.h).
#include "dba/io/stale_temporaries.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "dba/testing/temp_files.h"

namespace dba {
namespace {

namespace fs = std::filesystem;
using dba::testing::FreshTempDir;
using dba::testing::ReadFileBytes;
using dba::testing::WriteFileBytes;

// The pid of a process that has ended.
pid_t DeadPid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  ::waitpid(pid, nullptr, 0);
  return pid;
}

TEST(StaleTemporaries, DeadWritersTemporariesGoLiveOnesStay) {
  const std::string dir = FreshTempDir("stale_tmp");
  const std::string file = dir + "/out.txt";
  const std::string dead = file + ".tmp." + std::to_string(DeadPid());
  const std::string dead_call = file + ".tmp." + std::to_string(DeadPid()) + ".7";
  const std::string mine = TemporaryName(file);  // this live process's
  EXPECT_NE(mine, TemporaryName(file));          // one per call
  const std::string parent = file + ".tmp." + std::to_string(::getppid());
  const std::string other = file + ".tmp.12x";   // not a pid: not ours
  const std::string odd = file + ".tmp." + std::to_string(DeadPid()) + ".x";
  for (const std::string& p : {dead, dead_call, mine, parent, other, odd}) WriteFileBytes(p, "t");
  EXPECT_EQ(RecoverStaleTemporaries(file), 2);
  EXPECT_FALSE(fs::exists(dead));
  EXPECT_FALSE(fs::exists(dead_call));
  EXPECT_TRUE(fs::exists(odd));
  EXPECT_TRUE(fs::exists(mine));
  EXPECT_TRUE(fs::exists(parent));
  EXPECT_TRUE(fs::exists(other));
}

TEST(StaleTemporaries, LockedTemporaryOfAnUnknownPidStays) {
  // A writer on another machine sharing the directory: its pid is no process
  // here, but it holds the temporary's lock.
  const std::string dir = FreshTempDir("stale_locked");
  const std::string file = dir + "/out.txt";
  const std::string remote = file + ".tmp." + std::to_string(DeadPid());
  WriteFileBytes(remote, "t");
  const int lock = LockTemporary(remote);
  ASSERT_GE(lock, 0);
  const pid_t child = ::fork();  // a lock is held per open file: ask from another process
  if (child == 0) ::_exit(RecoverStaleTemporaries(file));
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_TRUE(fs::exists(remote));
  ::close(lock);
  EXPECT_EQ(RecoverStaleTemporaries(file), 1);
  EXPECT_FALSE(fs::exists(remote));
}

TEST(StaleTemporaries, InterruptedReplacementIsUndone) {
  const std::string dir = FreshTempDir("stale_backup");
  const std::string dead = std::to_string(DeadPid());
  // Replaced before the kill: the backup holds the old file.
  WriteFileBytes(dir + "/a.txt", "new a");
  WriteFileBytes(dir + "/a.txt.dba-old." + dead, "old a");
  // Not replaced yet: the backup is the file itself (a hard link).
  WriteFileBytes(dir + "/b.txt", "old b");
  ASSERT_EQ(::link((dir + "/b.txt").c_str(), (dir + "/b.txt.dba-old." + dead).c_str()), 0);
  EXPECT_EQ(RecoverStaleTemporaries(dir + "/a.txt"), 1);
  EXPECT_EQ(RecoverStaleTemporaries(dir + "/b.txt"), 1);
  EXPECT_EQ(ReadFileBytes(dir + "/a.txt"), "old a");
  EXPECT_EQ(ReadFileBytes(dir + "/b.txt"), "old b");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 2);
}

}  // namespace
}  // namespace dba
