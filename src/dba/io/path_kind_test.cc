// KindOfPath: the extensions, and names that only contain them.
#include "dba/io/path_kind.h"

#include <gtest/gtest.h>

namespace dba {
namespace {

TEST(PathKind, ByTheLastExtension) {
  EXPECT_EQ(KindOfPath("a/b/survey.dba"), PathKind::kBinary);
  EXPECT_EQ(KindOfPath("problem-49-7776-pre.txt.bz2"), PathKind::kBalBz2);
  EXPECT_EQ(KindOfPath("out.txt"), PathKind::kBalText);
  EXPECT_EQ(KindOfPath("model/sparse/0"), PathKind::kOther);
  EXPECT_EQ(KindOfPath("x.dba.json"), PathKind::kOther);
  EXPECT_EQ(KindOfPath("dba"), PathKind::kOther);
  EXPECT_EQ(KindOfPath(".txt.gz"), PathKind::kOther);
}

}  // namespace
}  // namespace dba
