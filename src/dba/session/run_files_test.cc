// A run's files: outputs naming inputs or each other are refused, naming
// both, unless the pair is in-place work the command allows.
#include "dba/session/run_files.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>

#include "dba/common/error.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

namespace fs = std::filesystem;
using dba::testing::FreshTempDir;
using dba::testing::WriteFileBytes;

std::string Refusal(const RunFiles& files) {
  try {
    files.Check();
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

TEST(RunFiles, OutputOverAnInputIsRefusedUnlessInPlace) {
  const std::string dir = FreshTempDir("run_files_inputs");
  WriteFileBytes(dir + "/a.txt", "x");
  RunFiles files;
  files.Input("INPUT", dir + "/a.txt");
  files.Output("-o", dir + "/a.txt");  // allowed: -o over the problem read
  files.Output("--checkpoint", dir + "/./b/../a.txt");
  fs::create_directories(dir + "/b");
  files.AllowInPlace("-o", "INPUT");
  const std::string why = Refusal(files);
  EXPECT_NE(why.find("name one file"), std::string::npos) << why;
  RunFiles one;
  one.Input("INPUT", dir + "/a.txt");
  one.Output("-o", dir + "/a.txt");
  one.Output("--checkpoint", dir + "/./b/../a.txt.ckpt");
  one.AllowInPlace("-o", "INPUT");
  EXPECT_NO_THROW(one.Check());
  RunFiles other;
  other.Input("INPUT", dir + "/a.txt");
  other.Output("--checkpoint", dir + "/./b/../a.txt");
  other.AllowInPlace("-o", "INPUT");
  const std::string refused = Refusal(other);
  EXPECT_NE(refused.find("--checkpoint " + dir + "/./b/../a.txt names INPUT " + dir + "/a.txt"),
            std::string::npos)
      << refused;
}

TEST(RunFiles, TwoOutputsOnOneFileAreRefused) {
  const std::string dir = FreshTempDir("run_files_outputs");
  RunFiles files;
  files.Output("-o", dir + "/b.txt");
  files.Output("--report", dir + "/sub/../b.txt");
  fs::create_directories(dir + "/sub");
  const std::string why = Refusal(files);
  EXPECT_NE(why.find("-o " + dir + "/b.txt and --report " + dir + "/sub/../b.txt name one file"),
            std::string::npos)
      << why;
  EXPECT_FALSE(fs::exists(dir + "/b.txt"));
}

TEST(RunFiles, ModelOutputCollidesWithItsFiles) {
  const std::string dir = FreshTempDir("run_files_model");
  RunFiles files;
  files.ModelOutput("-o", dir + "/model", ColmapFormat::kText);
  files.Output("--ply", dir + "/model/points3D.txt");
  EXPECT_NE(Refusal(files).find("name one file"), std::string::npos);
  RunFiles fine;
  fine.ModelOutput("-o", dir + "/model", ColmapFormat::kBinary);
  fine.Output("--ply", dir + "/points.ply");
  EXPECT_NO_THROW(fine.Check());
  EXPECT_FALSE(fs::exists(dir + "/model"));  // checked, not made
}

TEST(RunFiles, ModelWrittenOverItselfIsInPlace) {
  const std::string dir = FreshTempDir("run_files_model_in_place");
  for (const char* f : {"cameras.txt", "images.txt", "points3D.txt"}) WriteFileBytes(dir + "/" + f, "x");
  RunFiles files;
  files.Input("INPUT", dir);
  files.ModelOutput("-o", dir, ColmapFormat::kText);
  files.AllowInPlace("-o", "INPUT");
  EXPECT_NO_THROW(files.Check());
  files.Output("--report", dir + "/images.txt");
  EXPECT_NE(Refusal(files).find("-o " + dir + "/images.txt and --report " + dir +
                               "/images.txt name one file"),
            std::string::npos);
  RunFiles binary;
  binary.Input("INPUT", dir);
  binary.ModelOutput("-o", dir, ColmapFormat::kBinary);
  binary.Output("--report", dir + "/images.txt");
  binary.AllowInPlace("-o", "INPUT");
  EXPECT_NE(Refusal(binary).find("--report " + dir + "/images.txt names INPUT"), std::string::npos);
}

// A model's rigs and frames are its files too: an output naming one of an
// input model's is refused, and so is an output inside a model written that
// names one of the files a reader of it takes, whichever format.
TEST(RunFiles, EveryFileOfAModelIsTheModels) {
  const std::string dir = FreshTempDir("run_files_rigs");
  fs::create_directories(dir + "/m");
  for (const char* f : {"cameras.txt", "images.txt", "points3D.txt", "rigs.txt", "frames.txt"}) {
    WriteFileBytes(dir + "/m/" + f, "x");
  }
  for (const char* f : {"rigs.txt", "frames.txt"}) {
    RunFiles files;
    files.Input("INPUT", dir + "/m");
    files.Output("--report", dir + "/m/" + f);
    EXPECT_EQ(Refusal(files), "--report " + dir + "/m/" + f + " names INPUT " + dir + "/m/" + f +
                                  ", which this run reads: the output would replace it");
  }
  for (const char* f : {"frames.txt", "rigs.bin", "cameras.bin"}) {
    RunFiles files;
    files.ModelOutput("-o", dir + "/out", ColmapFormat::kText);
    files.RewrittenOutput("--checkpoint", dir + "/out/" + f);
    EXPECT_EQ(Refusal(files), "--checkpoint " + dir + "/out/" + f + " is " + f +
                                  " of the COLMAP model -o " + dir +
                                  "/out: a reader of the model would take it for the model's own");
  }
  RunFiles with_rigs;  // a model written with its rigs: its own rigs.txt
  with_rigs.ModelOutput("-o", dir + "/out", ColmapFormat::kText, true);
  with_rigs.Output("--ply", dir + "/out/rigs.txt");
  EXPECT_EQ(Refusal(with_rigs), "-o " + dir + "/out/rigs.txt and --ply " + dir +
                                    "/out/rigs.txt name one file: one output would replace the other");
  fs::create_directories(dir + "/there");
  RunFiles beside;  // a file of another name beside the model
  beside.ModelOutput("-o", dir + "/there", ColmapFormat::kText, true);
  beside.RewrittenOutput("--checkpoint", dir + "/there/run.ckpt");
  EXPECT_NO_THROW(beside.Check());
  EXPECT_TRUE(fs::is_empty(dir + "/there"));
}

// Two new paths, one through "link/..": one file.
TEST(RunFiles, OutputsThroughALinkAndDotDotAreOneFile) {
  const std::string dir = FreshTempDir("run_files_link_dotdot");
  fs::create_directories(dir + "/deep/sub");
  fs::create_directory_symlink("deep/sub", dir + "/link");
  RunFiles files;
  files.RewrittenOutput("--checkpoint", dir + "/link/../c.ckpt");
  files.Output("--report", dir + "/deep/c.ckpt");
  EXPECT_EQ(Refusal(files), "--checkpoint " + dir + "/link/../c.ckpt and --report " + dir +
                                "/deep/c.ckpt name one file: one output would replace the other");
}

// A checkpoint is replaced at every write and read back: a FIFO (or a
// character device) would block the second write, and is refused.
TEST(RunFiles, ACheckpointIsAFile) {
  const std::string dir = FreshTempDir("run_files_fifo");
  ASSERT_EQ(::mkfifo((dir + "/fifo").c_str(), 0600), 0);
  RunFiles files;
  files.RewrittenOutput("--checkpoint", dir + "/fifo");
  EXPECT_EQ(Refusal(files), "--checkpoint " + dir + "/fifo: is a FIFO; --checkpoint writes a file "
                                "that it replaces at every write and --resume reads back: name a file");
  RunFiles report;  // any other output may be one
  report.Output("--report", dir + "/fifo");
  EXPECT_NO_THROW(report.Check());
}

}  // namespace
}  // namespace dba
