// AtomicOutputFile: only Commit() makes the file appear; anything else leaves
// no trace. Several files replaced together appear all or none: a rename
// that fails puts back what the earlier ones replaced (CommitTogether and
// OutputTransaction; a write that fails: tests/cli_outputs.sh under ulimit -f).
#include "dba/io/atomic_output_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <sys/stat.h>
#include <unistd.h>

#include <barrier>
#include <thread>

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

// Three files replaced together; the third's rename fails (its path became a
// non-empty directory after the check): the first two are put back as they
// were, the new file that had no old one is gone, and no temporary or backup
// is left.
TEST(AtomicOutputFile, FailedRenamePutsBackWhatWasReplaced) {
  const std::string dir = dba::testing::FreshTempDir("together_fails");
  dba::testing::WriteFileBytes(dir + "/a.txt", "old a");
  AtomicOutputFile a(dir + "/a.txt"), b(dir + "/b.txt"), c(dir + "/c.txt");
  a.Write("new a");
  b.Write("new b");
  c.Write("new c");
  std::filesystem::create_directories(dir + "/c.txt/occupied");
  try {
    CommitTogether({&a, &b, &c});
    FAIL() << "the third rename succeeded";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("c.txt"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("put back as they were"), std::string::npos) << e.what();
  }
  EXPECT_EQ(dba::testing::ReadFileBytes(dir + "/a.txt"), "old a");
  EXPECT_FALSE(std::filesystem::exists(dir + "/b.txt"));
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    EXPECT_TRUE(name == "a.txt" || name == "c.txt") << name;
  }
}

TEST(AtomicOutputFile, TransactionRenamesAllAtItsCommitOrNothing) {
  const std::string dir = dba::testing::FreshTempDir("transaction");
  dba::testing::WriteFileBytes(dir + "/kept.txt", "old");
  {
    OutputTransaction run;
    WriteFileAtomically(dir + "/kept.txt", "new");
    WriteFileAtomically(dir + "/other.txt", "new");
    EXPECT_EQ(dba::testing::ReadFileBytes(dir + "/kept.txt"), "old");  // not yet
  }  // never committed: nothing of it appears
  EXPECT_EQ(dba::testing::ReadFileBytes(dir + "/kept.txt"), "old");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            1);
  OutputTransaction run;
  WriteFileAtomically(dir + "/kept.txt", "new");
  WriteFileAtomically(dir + "/other.txt", "other");
  run.Commit();
  EXPECT_EQ(dba::testing::ReadFileBytes(dir + "/kept.txt"), "new");
  EXPECT_EQ(dba::testing::ReadFileBytes(dir + "/other.txt"), "other");
  EXPECT_EQ(OutputTransaction::Current(), nullptr);
}

// Two threads of one process writing one file (two Python threads calling
// dba.solve with one report): each call has its own temporary, both
// commit, and the file is one of the two whole.
TEST(AtomicOutputFile, TwoThreadsWritingOneFileEachHaveTheirOwnTemporary) {
  const std::string dir = dba::testing::FreshTempDir("two_threads");
  const std::string path = dir + "/report.json";
  const std::string a(1 << 20, 'a'), b(1 << 19, 'b');
  std::barrier both_open(2);
  std::string errors[2];
  auto write = [&](int k, const std::string& contents) {
    bool arrived = false;
    try {
      AtomicOutputFile out(path);
      arrived = true;
      both_open.arrive_and_wait();  // both temporaries exist before either is written
      out.Write(contents);
      out.Commit();
    } catch (const std::exception& e) {
      errors[k] = e.what();
      if (!arrived) both_open.arrive_and_drop();
    }
  };
  std::thread first(write, 0, a), second(write, 1, b);
  first.join();
  second.join();
  EXPECT_EQ(errors[0], "");
  EXPECT_EQ(errors[1], "");
  const std::string got = dba::testing::ReadFileBytes(path);
  EXPECT_TRUE(got == a || got == b) << got.size() << " bytes, neither whole";
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir),
                          std::filesystem::directory_iterator()),
            1);
}

TEST(AtomicOutputFile, ReplacedFileKeepsItsMode) {
  const std::string dir = dba::testing::FreshTempDir("keep_mode");
  dba::testing::WriteFileBytes(dir + "/private.txt", "old");
  ::chmod((dir + "/private.txt").c_str(), 0600);
  WriteFileAtomically(dir + "/private.txt", "new");
  struct stat st {};
  ASSERT_EQ(::stat((dir + "/private.txt").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
}

TEST(AtomicOutputFile, FifoIsWrittenInPlace) {
  const std::string dir = dba::testing::FreshTempDir("fifo_out");
  const std::string fifo = dir + "/fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string got;
  std::thread reader([&] { got = dba::testing::ReadFileBytes(fifo); });
  WriteFileAtomically(fifo, "through the pipe");
  reader.join();
  EXPECT_EQ(got, "through the pipe");
  struct stat st {};
  ASSERT_EQ(::lstat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
}

}  // namespace
}  // namespace dba
