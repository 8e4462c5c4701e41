// Blocks copied and added as they are or transposed, against Eigen's
// transpose; the block row found for every block.
#include "dba/cluster/block_transfer.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

namespace dba {
namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Rows sized 6 and 9, blocks (0,0), (0,1), (1,1), values 1, 2, 3, ...
BsmcMatrix TwoRows() {
  const std::vector<uint64_t> pattern = {PackBlock(0, 0), PackBlock(0, 1), PackBlock(1, 1)};
  BsmcMatrix m = BsmcMatrix::BuildFromPattern({6, 9}, pattern);
  for (int64_t k = 0; k < m.num_values(); ++k) m.values()[k] = 1.0 + static_cast<double>(k);
  return m;
}

TEST(BlockTransfer, CopiesAndAddsABlockAsItIsOrTransposed) {
  BsmcMatrix m = TwoRows();
  const Eigen::Map<const RowMajor> block(m.block_values(1), 6, 9);
  std::vector<double> out(54, 0.0);
  EXPECT_EQ(CopyBlock(m, 1, false, out.data()), out.data() + 54);
  EXPECT_EQ(Eigen::Map<const RowMajor>(out.data(), 6, 9), block);
  EXPECT_EQ(CopyBlock(m, 1, true, out.data()), out.data() + 54);
  const RowMajor transposed = Eigen::Map<const RowMajor>(out.data(), 9, 6);
  EXPECT_EQ(transposed, block.transpose());
  const RowMajor before = block;
  EXPECT_EQ(AddToBlock(out.data(), true, 1, &m), out.data() + 54);  // += (Bᵀ)ᵀ
  EXPECT_EQ(Eigen::Map<const RowMajor>(m.block_values(1), 6, 9), 2.0 * before);
  EXPECT_EQ(AddToBlock(out.data(), false, 0, &m) - out.data(), 36);  // a 6 x 6 block
}

TEST(BlockTransfer, FindsEachBlocksRow) {
  const BsmcMatrix m = TwoRows();
  EXPECT_EQ(BlockRow(m, 0), 0);
  EXPECT_EQ(BlockRow(m, 1), 0);
  EXPECT_EQ(BlockRow(m, 2), 1);
}

}  // namespace
}  // namespace dba
