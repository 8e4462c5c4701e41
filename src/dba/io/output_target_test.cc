// The output rule (io/output_target.h) on every kind of path: what is
// replaced, what is written in place, what is refused and how two names of
// one file are told to be one.
#include "dba/io/output_target.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <stdexcept>

#include "dba/common/error.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

namespace fs = std::filesystem;
using dba::testing::FreshTempDir;
using dba::testing::WriteFileBytes;

TEST(OutputTarget, RegularAndNewFilesAreReplaced) {
  const std::string dir = FreshTempDir("target_regular");
  WriteFileBytes(dir + "/old.txt", "x");
  const OutputTarget old = ResolveOutputTarget(dir + "/old.txt");
  EXPECT_EQ(old.mode, OutputMode::kReplace);
  EXPECT_EQ(old.file, fs::canonical(dir + "/old.txt").string());
  const OutputTarget fresh = ResolveOutputTarget(dir + "/new.txt");
  EXPECT_EQ(fresh.mode, OutputMode::kReplace);
  EXPECT_EQ(fresh.file, (fs::canonical(dir) / "new.txt").string());
  EXPECT_NO_THROW(CheckCreatable(fresh));
  EXPECT_FALSE(fs::exists(dir + "/new.txt"));  // the check leaves nothing
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(OutputTarget, SymbolicLinksAreWrittenThrough) {
  const std::string dir = FreshTempDir("target_link");
  WriteFileBytes(dir + "/real.txt", "x");
  fs::create_symlink("real.txt", dir + "/link.txt");
  const OutputTarget t = ResolveOutputTarget(dir + "/link.txt");
  EXPECT_EQ(t.file, fs::canonical(dir + "/real.txt").string());
  EXPECT_EQ(t.identity, *ExistingFileIdentity(dir + "/real.txt"));
  fs::create_symlink(dir + "/nowhere/x", dir + "/dangling");
  EXPECT_THROW(ResolveOutputTarget(dir + "/dangling"), UsageError);
}

TEST(OutputTarget, DirectoriesSocketsAndProcAreRefused) {
  const std::string dir = FreshTempDir("target_refused");
  EXPECT_THROW(ResolveOutputTarget(dir), UsageError);
  EXPECT_THROW(ResolveOutputTarget(""), UsageError);
  EXPECT_THROW(ResolveOutputTarget("/proc/self/status"), UsageError);
  EXPECT_THROW(ResolveOutputTarget("/proc/dba_test_new_file"), UsageError);
  try {
    ResolveOutputTarget(dir + "/missing/x.txt");
    FAIL() << "a missing directory was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
  // A model file whose directory is made when missing: its directory's
  // directory must exist.
  EXPECT_NO_THROW(ResolveOutputTarget(dir + "/model/cameras.txt", true));
  EXPECT_THROW(ResolveOutputTarget(dir + "/a/model/cameras.txt", true), std::runtime_error);
}

TEST(OutputTarget, FifosAreStreams) {
  const std::string dir = FreshTempDir("target_fifo");
  ASSERT_EQ(::mkfifo((dir + "/fifo").c_str(), 0600), 0);
  const OutputTarget t = ResolveOutputTarget(dir + "/fifo");
  EXPECT_EQ(t.mode, OutputMode::kStream);
  EXPECT_NO_THROW(CheckCreatable(t));
}

TEST(OutputTarget, OneFileHasOneIdentityHoweverItIsNamed) {
  const std::string dir = FreshTempDir("target_identity");
  fs::create_directories(dir + "/sub");
  WriteFileBytes(dir + "/sub/f.txt", "x");
  EXPECT_EQ(PathIdentity(dir + "/sub/f.txt"), PathIdentity(dir + "/./sub/../sub/f.txt"));
  ::link((dir + "/sub/f.txt").c_str(), (dir + "/hard.txt").c_str());
  EXPECT_EQ(PathIdentity(dir + "/sub/f.txt"), PathIdentity(dir + "/hard.txt"));
  // Paths that do not exist yet: by the deepest directory that does.
  EXPECT_EQ(PathIdentity(dir + "/new/a.txt"), PathIdentity(dir + "/sub/../new/./a.txt"));
  EXPECT_NE(PathIdentity(dir + "/new/a.txt"), PathIdentity(dir + "/new/b.txt"));
  EXPECT_EQ(PathIdentity(dir + "/new/a.txt").rest, "new/a.txt");
}

// "link/.." is the directory above the one the link leads to, not the one
// holding the link: a new path through it is the file beside the link's
// target (as the kernel resolves it), never the one a lexical ".." gives.
TEST(OutputTarget, DotDotThroughALinkIsResolvedByTheFileSystem) {
  const std::string dir = FreshTempDir("target_link_dotdot");
  fs::create_directories(dir + "/deep/sub");
  fs::create_directory_symlink("deep/sub", dir + "/link");
  EXPECT_EQ(PathIdentity(dir + "/link/../c.ckpt"), PathIdentity(dir + "/deep/c.ckpt"));
  EXPECT_NE(PathIdentity(dir + "/link/../c.ckpt"), PathIdentity(dir + "/c.ckpt"));
  EXPECT_EQ(PathIdentity(dir + "/link/../new/./x/../c.ckpt"), PathIdentity(dir + "/deep/new/c.ckpt"));
  EXPECT_EQ(PathIdentity(dir + "/link/../new/c.ckpt").rest, "new/c.ckpt");
  EXPECT_EQ(ResolveOutputTarget(dir + "/link/../c.ckpt").file,
            (fs::canonical(dir) / "deep/c.ckpt").string());
}

TEST(OutputTarget, ReadOnlyDirectoryFailsTheCheck) {
  if (::geteuid() == 0) GTEST_SKIP() << "root writes into read-only directories";
  const std::string dir = FreshTempDir("target_readonly");
  ::chmod(dir.c_str(), 0555);
  EXPECT_THROW(CheckCreatable(ResolveOutputTarget(dir + "/x.txt")), std::runtime_error);
  ::chmod(dir.c_str(), 0755);
}

}  // namespace
}  // namespace dba
