// The RCS spread over the ranks, planned: owners by the most values (ties
// to the lowest rank), balanced when one rank would hold too much, and a
// reduce-scatter simulated with the plans alone (no transport): every
// owner's rows of S are the sum of the ranks' sub-RCSs, against a dense
// reference.
#include "dba/cluster/rcs_row_plan.h"

#include "dba/cluster/block_transfer.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

namespace dba {
namespace {

TEST(RcsRowPlan, OwnerHasTheMostValuesTiesToTheLowestRank) {
  // Rows 0..3; counts per rank.
  const std::vector<std::vector<int64_t>> counts = {{5, 0, 2, 1}, {3, 4, 2, 0}, {0, 4, 1, 0}};
  std::vector<int64_t> max(4, 0);
  for (int r = 0; r < 3; ++r) {
    const std::vector<int64_t> key = OwnerKeys(counts[r], 3, r);
    for (int g = 0; g < 4; ++g) max[g] = std::max(max[g], key[g]);
  }
  EXPECT_EQ(OwnersFromKeys(max, 3), (std::vector<int32_t>{0, 1, 0, 0}));
}

TEST(RcsRowPlan, APiledUpLoadIsSpreadInContiguousRanges) {
  std::vector<int32_t> owner(6, 0);
  const std::vector<int64_t> weight(6, 10);
  BalanceOwnerLoad(weight, {1, 1, 1}, &owner);
  EXPECT_EQ(owner, (std::vector<int32_t>{0, 0, 1, 1, 2, 2}));
  std::vector<int32_t> even = {0, 1, 2, 0, 1, 2};
  BalanceOwnerLoad(weight, {1, 1, 1}, &even);
  EXPECT_EQ(even, (std::vector<int32_t>{0, 1, 2, 0, 1, 2}));  // balanced already
  std::vector<int32_t> to_formers(4, 0);
  BalanceOwnerLoad(std::vector<int64_t>(4, 1), {0, 1, 1}, &to_formers);  // rank 0 forms nothing
  EXPECT_EQ(to_formers, (std::vector<int32_t>{1, 1, 2, 2}));
}

// Ranges along the cameras' places: rows 5, 0, 3 (the first in that order)
// go to one rank whatever their numbers.
TEST(RcsRowPlan, APiledUpLoadIsSpreadInRangesOfTheGivenOrder) {
  std::vector<int32_t> owner(6, 0);
  BalanceOwnerLoad(std::vector<int64_t>(6, 10), {1, 1}, &owner, {5, 0, 3, 1, 4, 2});
  EXPECT_EQ(owner, (std::vector<int32_t>{0, 1, 1, 0, 1, 0}));
}

// Symmetric counts: a full sub-RCS of rows sized 6, 6, 9 puts s_i * 21
// values into row i of the symmetric matrix, whichever rows come first;
// the upper triangle's counts follow the global numbering (a block goes to
// its lower global row: global rows 1, 2, 4 store 126, 135 and 36).
TEST(RcsRowPlan, SymmetricCountsDoNotDependOnTheRowsNumbering) {
  std::vector<uint64_t> pattern;
  for (int32_t i = 0; i < 3; ++i) {
    for (int32_t j = i; j < 3; ++j) pattern.push_back(PackBlock(i, j));
  }
  const BsmcMatrix sub = BsmcMatrix::BuildFromPattern({6, 6, 9}, pattern);
  const std::vector<int32_t> rows = {4, 1, 2};
  EXPECT_EQ(SymmetricRowValueCounts(&sub, rows, 5), (std::vector<int64_t>{0, 126, 189, 0, 126}));
  EXPECT_EQ(RowValueCounts(&sub, rows, 5), (std::vector<int64_t>{0, 126, 135, 0, 36}));
  EXPECT_EQ(SymmetricRowValueCounts(nullptr, rows, 2), (std::vector<int64_t>{0, 0}));
}

// A sub-RCS over `rows` (global ids, in any order) with every block
// present, values from `seed`; and its dense contribution to the global
// symmetric matrix (both triangles).
BsmcMatrix SubRcs(const std::vector<int32_t>& rows, const std::vector<int32_t>& sizes, double seed,
                  Eigen::MatrixXd* global, const std::vector<int64_t>& offset) {
  std::vector<int32_t> local_sizes;
  std::vector<uint64_t> pattern;
  for (size_t i = 0; i < rows.size(); ++i) {
    local_sizes.push_back(sizes[rows[i]]);
    for (size_t j = i; j < rows.size(); ++j) pattern.push_back(PackBlock(int32_t(i), int32_t(j)));
  }
  BsmcMatrix m = BsmcMatrix::BuildFromPattern(local_sizes, pattern);
  for (int32_t i = 0; i < m.num_block_rows(); ++i) {
    for (int64_t b = m.row_begin(i); b < m.row_end(i); ++b) {
      const int32_t j = m.block_col(b);
      double* v = m.block_values(b);
      for (int r = 0; r < m.block_size(i); ++r) {
        for (int c = 0; c < m.block_size(j); ++c) {
          const double x = seed + 0.01 * (10 * rows[i] + rows[j]) + 0.001 * (4 * r + c);
          v[r * m.block_size(j) + c] = x;
          (*global)(offset[rows[i]] + r, offset[rows[j]] + c) += x;
          if (i != j) (*global)(offset[rows[j]] + c, offset[rows[i]] + r) += x;
        }
      }
    }
  }
  return m;
}

// Rank 1's rows come in decreasing global order (a walked share's cameras):
// its off-diagonal blocks land transposed.
TEST(RcsRowPlan, SimulatedReduceScatterSumsTheGlobalRcs) {
  const std::vector<int32_t> sizes = {2, 3, 2, 1};
  std::vector<int64_t> offset = {0};
  for (int32_t s : sizes) offset.push_back(offset.back() + s);
  Eigen::MatrixXd global = Eigen::MatrixXd::Zero(offset.back(), offset.back());
  const std::vector<std::vector<int32_t>> rows = {{0, 1, 2}, {3, 2, 1}};
  std::vector<BsmcMatrix> subs;
  for (int r = 0; r < 2; ++r) subs.push_back(SubRcs(rows[r], sizes, 1.0 + r, &global, offset));
  const std::vector<int32_t> owner = {0, 0, 1, 1};
  std::vector<SubRcsSendPlan> sends;
  for (int r = 0; r < 2; ++r) sends.push_back(PlanSubRcsSends(&subs[r], rows[r], owner, 2));
  for (int me = 0; me < 2; ++me) {
    std::vector<std::vector<uint64_t>> patterns = {sends[0].pattern[me], sends[1].pattern[me]};
    std::vector<std::vector<int32_t>> row_ids = {sends[0].row_ids[me], sends[1].row_ids[me]};
    std::vector<int32_t> own;
    for (int32_t g = 0; g < 4; ++g) {
      if (owner[g] == me) own.push_back(g);
    }
    const std::vector<int32_t> local = LocalRows(own, patterns, owner, me);
    std::vector<int32_t> local_of(4, -1), local_sizes;
    for (size_t l = 0; l < local.size(); ++l) {
      local_of[local[l]] = static_cast<int32_t>(l);
      local_sizes.push_back(sizes[local[l]]);
    }
    BsmcMatrix S = BsmcMatrix::BuildFromPattern(
        local_sizes, LocalPattern(static_cast<int32_t>(local.size()), patterns, local_of));
    S.SetZero();
    const ReceivePlan receive = PlanReceives(S, patterns, row_ids, local_of, sizes);
    for (int from = 0; from < 2; ++from) {  // the message's blocks, added where they land
      for (size_t k = 0; k < sends[from].blocks[me].size(); ++k) {
        const int64_t b = sends[from].blocks[me][k];
        std::vector<double> message(subs[from].value_offset(b + 1) - subs[from].value_offset(b));
        CopyBlock(subs[from], b, sends[from].transposed[me][k] != 0, message.data());
        AddToBlock(message.data(), false, receive.blocks[from][k], &S);
      }
    }
    // Every own row's blocks equal the global matrix's.
    for (int32_t l = 0; l < static_cast<int32_t>(own.size()); ++l) {
      for (int64_t b = S.row_begin(l); b < S.row_end(l); ++b) {
        const int32_t gi = local[l], gj = local[S.block_col(b)];
        for (int r = 0; r < sizes[gi]; ++r) {
          for (int c = 0; c < sizes[gj]; ++c) {
            EXPECT_DOUBLE_EQ(S.block_values(b)[r * sizes[gj] + c], global(offset[gi] + r, offset[gj] + c))
                << "rank " << me << " block (" << gi << ", " << gj << ")";
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace dba
