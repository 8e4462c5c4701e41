// An input's kind decided by its content (not its name), and a problem of
// every kind read through one call, against the kind's own reader.
#include "dba/io/input_source.h"

#include <gtest/gtest.h>

#include <fstream>

#include "dba/common/error.h"
#include "dba/io/bal_writer.h"
#include "dba/io/binary_problem.h"
#include "dba/io/colmap_binary.h"
#include "dba/io/colmap_problem.h"
#include "dba/io/colmap_text.h"
#include "dba/io/read_problem.h"
#include "dba/testing/synthetic_bal.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

const std::string kColmap = std::string(DBA_SHARED_DATA_DIR) + "/colmap/mithunnallana_6img/sparse/0";

Problem SmallBal() {
  testing::SyntheticBalOptions o;
  o.num_cameras = 4;
  o.num_points = 30;
  return testing::MakeSyntheticBal(o).problem;
}

TEST(InputSource, KindsComeFromTheContentNotTheName) {
  const Problem p = SmallBal();
  const std::string bal = testing::TempPath("kind_bal.dba");  // BAL text named .dba
  WriteBal(p, bal);
  const std::string binary = testing::TempPath("kind_binary.txt");  // a .dba named .txt
  WriteBinaryProblem(p, binary);
  EXPECT_EQ(DecideInput(bal).kind, InputKind::kBalText);
  EXPECT_EQ(DecideInput(binary).kind, InputKind::kBinary);
  EXPECT_STREQ(DecideInput(binary).KindName(), "dba binary");
  const InputSource colmap = DecideInput(kColmap);
  EXPECT_TRUE(colmap.colmap());
  EXPECT_EQ(colmap.colmap_format, ColmapFormat::kText);  // as shipped
  EXPECT_STREQ(colmap.KindName(), "COLMAP model");
  const std::string binary_model = testing::FreshTempDir("kind_colmap_binary");
  WriteColmapBinary(ReadColmapModel(kColmap), binary_model);
  EXPECT_EQ(DecideInput(binary_model).colmap_format, ColmapFormat::kBinary);
  // A directory without a model, a missing path: BAL text, whose reader
  // says what is wrong.
  EXPECT_EQ(DecideInput(testing::FreshTempDir("kind_empty")).kind, InputKind::kBalText);
  EXPECT_EQ(DecideInput(testing::TempPath("kind_missing.txt")).kind, InputKind::kBalText);
  EXPECT_THROW(ReadInputProblem(DecideInput(testing::FreshTempDir("kind_empty2")), DefaultFixings()),
               InputError);
}

TEST(InputSource, ReadsEveryKindAsItsOwnReaderDoes) {
  const Problem p = SmallBal();
  const std::string path = testing::TempPath("read_any.dba");
  WriteBinaryProblem(p, path);
  const Problem binary = ReadInputProblem(DecideInput(path), DefaultFixings());
  EXPECT_EQ(binary.cameras, ReadProblem(path).cameras);
  EXPECT_EQ(binary.obs_pixel, p.obs_pixel);
  const Problem colmap = ReadInputProblem(DecideInput(kColmap), DefaultFixings());
  const ColmapProblem own = ProblemFromColmap(ReadColmapModel(kColmap), {}, kColmap);
  EXPECT_EQ(colmap.num_images(), own.problem.num_images());
  EXPECT_EQ(colmap.points, own.problem.points);
  // The principal points held (DefaultFixings): every group has a mask.
  ASSERT_EQ(static_cast<int64_t>(colmap.fixed_intrinsics.size()), colmap.num_groups());
  for (uint16_t mask : colmap.fixed_intrinsics) EXPECT_NE(mask, 0);
}

}  // namespace
}  // namespace dba
