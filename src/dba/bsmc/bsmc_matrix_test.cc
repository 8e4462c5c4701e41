// BSMC structure: block lookup both ways, value layout, exact byte counts
// against the array sizes and against a dense count of CSR non-zeros.
#include "dba/bsmc/bsmc_matrix.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <climits>
#include <set>

#include "dba/testing/dense_reference.h"
#include "dba/testing/random_bsmc.h"

namespace dba {
namespace {

TEST(BsmcMatrix, FindBlockFindsEveryStoredBlockAndNoOther) {
  for (uint32_t seed = 1; seed <= 5; ++seed) {
    testing::RandomBsmcOptions o;
    o.block_rows = 30;
    o.seed = seed;
    const BsmcMatrix m = testing::MakeRandomBsmc(o);
    std::set<std::pair<int32_t, int32_t>> stored;
    for (int32_t i = 0; i < m.num_block_rows(); ++i) {
      for (int64_t b = m.row_begin(i); b < m.row_end(i); ++b) {
        stored.insert({i, m.block_col(b)});
        EXPECT_EQ(m.FindBlock(i, m.block_col(b)), b);
        EXPECT_EQ(m.BlockRow(b), i);
      }
    }
    for (int32_t i = 0; i < m.num_block_rows(); ++i) {
      for (int32_t j = i; j < m.num_block_rows(); ++j) {
        if (!stored.count({i, j})) {
          EXPECT_EQ(m.FindBlock(i, j), -1) << i << "," << j;
        }
      }
    }
  }
}

TEST(BsmcMatrix, SeekBlockFromAnyEarlierBlockAgreesWithFindBlock) {
  for (uint32_t seed = 1; seed <= 5; ++seed) {
    testing::RandomBsmcOptions o;
    o.block_rows = 40;
    o.fill = seed * 0.2;  // sparse rows to full ones
    o.seed = seed;
    const BsmcMatrix m = testing::MakeRandomBsmc(o);
    for (int32_t i = 0; i < m.num_block_rows(); ++i) {
      for (int64_t from = m.row_begin(i); from < m.row_end(i); ++from) {
        for (int32_t j = m.block_col(from); j < m.num_block_rows(); ++j) {
          ASSERT_EQ(m.SeekBlock(from, i, j), m.FindBlock(i, j))
              << "seed " << seed << ", row " << i << ", from block " << from << ", column " << j;
        }
      }
    }
  }
}

TEST(BsmcMatrix, ValuesAreContiguousBlocksOfTheRightSize) {
  testing::RandomBsmcOptions o;
  o.seed = 7;
  const BsmcMatrix m = testing::MakeRandomBsmc(o);
  int64_t expected = 0;
  for (int32_t i = 0; i < m.num_block_rows(); ++i) {
    EXPECT_EQ(m.block_col(m.diagonal_block(i)), i);
    for (int64_t b = m.row_begin(i); b < m.row_end(i); ++b) {
      EXPECT_EQ(m.value_offset(b), expected);
      expected += int64_t{m.block_size(i)} * m.block_size(m.block_col(b));
    }
  }
  EXPECT_EQ(m.num_values(), expected);
}

TEST(BsmcMatrix, ByteCountsAreExact) {
  testing::RandomBsmcOptions o;
  o.block_rows = 25;
  o.seed = 11;
  const BsmcMatrix m = testing::MakeRandomBsmc(o);
  const int64_t n = m.num_block_rows(), nnzb = m.num_blocks();
  // block_size (4 n) + scalar_offset (8 (n+1)) + row_begin (8 (n+1)) +
  // block_col (4 nnzb) + value_offset (8 (nnzb+1)).
  EXPECT_EQ(m.StructureBytes(), 4 * n + 16 * (n + 1) + 4 * nnzb + 8 * (nnzb + 1));
  EXPECT_EQ(m.ValueBytes(), 8 * m.num_values());
  // CSR: count the non-zeros of the dense symmetric matrix (values are
  // random, so no stored entry is zero).
  const Eigen::MatrixXd dense = testing::DenseFromBsmc(m);
  int64_t nnz = 0, nnz_upper = 0;
  for (int64_t r = 0; r < dense.rows(); ++r) {
    for (int64_t c = 0; c < dense.cols(); ++c) {
      if (dense(r, c) != 0.0) ++nnz, nnz_upper += c >= r;
    }
  }
  EXPECT_EQ(m.CsrBytes(false), nnz * 12 + (dense.rows() + 1) * 8);
  EXPECT_EQ(m.CsrBytes(true), nnz_upper * 12 + (dense.rows() + 1) * 8);
  EXPECT_LT(m.StructureBytes() + m.ValueBytes(), m.CsrBytes(false));
}

// The structure alone says what its values will take; allocated, it is the
// matrix BuildFromPattern makes.
TEST(BsmcMatrix, StructureAloneSizesItsValues) {
  const std::vector<int32_t> sizes = {9, 6, 5};
  const std::vector<uint64_t> pattern = {PackBlock(0, 0), PackBlock(0, 2), PackBlock(1, 1),
                                         PackBlock(2, 2)};
  BsmcMatrix m = BsmcMatrix::BuildStructure(sizes, pattern);
  EXPECT_FALSE(m.has_values());
  EXPECT_TRUE(m.values().empty());
  EXPECT_EQ(m.num_values(), 81 + 45 + 36 + 25);
  EXPECT_EQ(m.ValueBytes(), 8 * (81 + 45 + 36 + 25));
  m.AllocateValues();
  EXPECT_TRUE(m.has_values());
  const BsmcMatrix full = BsmcMatrix::BuildFromPattern(sizes, pattern);
  EXPECT_TRUE(std::ranges::equal(m.values(), full.values()));
  EXPECT_EQ(m.StructureBytes(), full.StructureBytes());
}

// Values given back between solves read zero, a SetZero after them writes
// nothing and leaves them zero, and they take values again as written.
TEST(BsmcMatrix, ValuesGivenBackReadZeroUntilWritten) {
  std::vector<uint64_t> blocks;
  for (int32_t i = 0; i < 300; ++i) {
    blocks.push_back(PackBlock(i, i));
    if (i + 1 < 300) blocks.push_back(PackBlock(i, i + 1));
  }
  BsmcMatrix m = BsmcMatrix::BuildFromPattern(std::vector<int32_t>(300, 9), blocks);
  ASSERT_GT(m.ValueBytes(), 16 * 4096);  // whole pages inside
  for (int round = 0; round < 2; ++round) {
    m.SetZero();
    for (double& v : m.values()) EXPECT_EQ(v, 0.0);
    std::fill(m.values().begin(), m.values().end(), 1.5 + round);
    m.ZeroValuesAndReturnPages();
    for (double& v : m.values()) ASSERT_EQ(v, 0.0) << "round " << round;
    EXPECT_FALSE(m.values_narrowed());
  }
  // A SetZero with values written since (no pages given back) zeroes them.
  m.SetZero();
  m.values()[7] = 3.0;
  m.SetZero();
  EXPECT_EQ(m.values()[7], 0.0);
}

TEST(BsmcMatrix, RefusesBadPatterns) {
  const std::vector<int32_t> sizes = {2, 2, 2};
  auto build = [&](std::vector<uint64_t> p) { return BsmcMatrix::BuildFromPattern(sizes, p); };
  EXPECT_NO_THROW(build({PackBlock(0, 0), PackBlock(0, 2), PackBlock(1, 1), PackBlock(2, 2)}));
  EXPECT_THROW(build({PackBlock(0, 2), PackBlock(0, 0), PackBlock(1, 1), PackBlock(2, 2)}),
               std::invalid_argument);  // unsorted
  EXPECT_THROW(build({PackBlock(0, 0), PackBlock(0, 0), PackBlock(1, 1), PackBlock(2, 2)}),
               std::invalid_argument);  // duplicate
  EXPECT_THROW(build({PackBlock(0, 0), PackBlock(1, 0), PackBlock(1, 1), PackBlock(2, 2)}),
               std::invalid_argument);  // lower triangle
  EXPECT_THROW(build({PackBlock(0, 0), PackBlock(0, 1), PackBlock(2, 2)}),
               std::invalid_argument);  // diagonal 1 missing
}

TEST(BsmcMatrix, PackedBlockIdsRoundTripNearInt32Max) {
  for (int32_t row : {0, 1, INT32_MAX - 1, INT32_MAX}) {
    for (int32_t col : {row, INT32_MAX}) {
      const uint64_t p = PackBlock(row, col);
      EXPECT_EQ(PackedRow(p), row);
      EXPECT_EQ(PackedCol(p), col);
    }
  }
  EXPECT_LT(PackBlock(INT32_MAX - 1, INT32_MAX), PackBlock(INT32_MAX, INT32_MAX));
}

}  // namespace
// Values at a lent place: read and written there, left there by
// ZeroValuesAndReturnPages (the lender's pages) and zeroed by the next
// SetZero; placed back in storage of their own, zero.
TEST(BsmcMatrix, LentValuesLiveAtTheLentPlace) {
  const std::vector<uint64_t> pattern = {PackBlock(0, 0), PackBlock(0, 1), PackBlock(1, 1)};
  BsmcMatrix m = BsmcMatrix::BuildFromPattern({2, 3}, pattern);
  std::vector<double> place(m.num_values() + 1, 5.0);
  m.PlaceValues(place.data());
  EXPECT_TRUE(m.values_placed());
  EXPECT_TRUE(m.has_values());
  EXPECT_EQ(m.values().data(), place.data());
  EXPECT_EQ(m.values().size(), static_cast<size_t>(m.num_values()));
  EXPECT_EQ(m.block_values(1), place.data() + 4);
  m.SetZero();
  EXPECT_EQ(std::count(place.begin(), place.end(), 0.0), m.num_values());
  EXPECT_EQ(place.back(), 5.0);  // nothing written past the values
  m.block_values(2)[8] = 2.0;
  m.ZeroValuesAndReturnPages();
  EXPECT_EQ(place[m.num_values() - 1], 2.0);
  std::fill(place.begin(), place.end(), 4.0);  // the lender's meanwhile
  m.SetZero();
  EXPECT_EQ(std::count(place.begin(), place.end(), 0.0), m.num_values());
  // A copy holds its own values; a move takes the place with it.
  m.block_values(0)[1] = 7.0;
  const BsmcMatrix copy = m;
  EXPECT_FALSE(copy.values_placed());
  EXPECT_NE(copy.values().data(), place.data());
  EXPECT_TRUE(std::ranges::equal(copy.values(), m.values()));
  BsmcMatrix moved = std::move(m);
  EXPECT_EQ(moved.values().data(), place.data());
  m = std::move(moved);
  EXPECT_FALSE(moved.values_placed());  // NOLINT(bugprone-use-after-move): moved from
  EXPECT_EQ(m.values().data(), place.data());
  m.PlaceValues(nullptr);
  EXPECT_FALSE(m.values_placed());
  EXPECT_NE(m.values().data(), place.data());
  EXPECT_TRUE(std::ranges::all_of(m.values(), [](double v) { return v == 0.0; }));
}

}  // namespace dba
