// A run's files: outputs naming inputs or each other are refused, naming
// both, unless the pair is in-place work the command allows.
#include "dba/session/run_files.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace dba
