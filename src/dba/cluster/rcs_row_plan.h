// The planning of the RCS spread over the ranks (cluster/distributed_rcs.h,
// docs/design.md §4.1), as pure functions of what each rank knows or was
// sent: which rank owns each global block row, what a rank's sub-RCS sends
// to each owner, a rank's local numbering (own rows, then the halo) and the
// pattern of its part of S, and where each received block and row lands.
// DistributedRcs's constructor is these and the exchanges between them.
//
// Thread safety: pure functions.
#pragma once

#include <cstdint>
#include <vector>

#include "dba/bsmc/bsmc_matrix.h"

namespace dba {

// Values this rank's sub-RCS (`sub`, its rows' global ids `sub_rows`) puts
// into each of `n_global` rows (null `sub`: none).
std::vector<int64_t> RowValueCounts(const BsmcMatrix* sub, const std::vector<int32_t>& sub_rows,
                                    int32_t n_global);

// Values this rank's sub-RCS puts into each row of the whole symmetric
// matrix: a stored block (i, j), i < j, counts in row i and row j. Unlike
// RowValueCounts (the upper triangle's), it does not depend on how the rows
// are numbered: the owners chosen by it are the same for any numbering of
// the cameras.
std::vector<int64_t> SymmetricRowValueCounts(const BsmcMatrix* sub,
                                             const std::vector<int32_t>& sub_rows,
                                             int32_t n_global);

// The key each rank contributes to an all-reduced max per row: the row's
// value count, ties broken toward the lowest rank; and the owner that the
// max of the keys names.
std::vector<int64_t> OwnerKeys(const std::vector<int64_t>& counts, int ranks, int rank);
std::vector<int32_t> OwnersFromKeys(const std::vector<int64_t>& max_keys, int ranks);

// The owners as chosen, unless that piles the RCS on a few ranks: past 1.25x
// the mean load (`weight`: every rank's value counts summed, each row + 1),
// the rows go in contiguous ranges of equal load to the ranks that form
// (`forms`: 1 for a rank with points), ranges of `order` (the rows by their
// cameras' places, rcs/aggregation_order.h: each rank then owns a compact
// block of cameras whatever their numbering; empty: row order).
void BalanceOwnerLoad(const std::vector<int64_t>& weight, const std::vector<int64_t>& forms,
                      std::vector<int32_t>* owner, const std::vector<int32_t>& order = {});

// What a rank's sub-RCS sends to each owner: its blocks (sub's block
// indices, and packed (global row, global col), row <= col) and its rows
// (sub's row indices, and their global ids), in sub's order. A block whose
// local rows come in the reverse of their global order (a share whose
// cameras are numbered by its walk, cluster/rank_share.h) is the global
// block (j, i) transposed: it goes to the owner of row j, `transposed` set.
struct SubRcsSendPlan {
  std::vector<std::vector<int64_t>> blocks;
  std::vector<std::vector<uint8_t>> transposed;
  std::vector<std::vector<uint64_t>> pattern;
  std::vector<std::vector<int32_t>> rows, row_ids;
};
SubRcsSendPlan PlanSubRcsSends(const BsmcMatrix* sub, const std::vector<int32_t>& sub_rows,
                               const std::vector<int32_t>& owner, int ranks);


// A rank's local rows: its own (global order), then the halo: the columns
// of the blocks it receives (`patterns`, packed global (row, col)) owned
// elsewhere, in global order.
std::vector<int32_t> LocalRows(const std::vector<int32_t>& own,
                               const std::vector<std::vector<uint64_t>>& patterns,
                               const std::vector<int32_t>& owner, int rank);

// The pattern of a rank's part of S over its local rows (`local_of`: global
// row -> local, -1 elsewhere): every diagonal block, and the received ones.
std::vector<uint64_t> LocalPattern(int32_t local_rows,
                                   const std::vector<std::vector<uint64_t>>& patterns,
                                   const std::vector<int32_t>& local_of);

// Where each received block lands in S (its block index) and each received
// row (its local row), per sending rank; and the doubles of each message.
struct ReceivePlan {
  std::vector<std::vector<int64_t>> blocks;
  std::vector<std::vector<int32_t>> rows;
  std::vector<int64_t> size;
};
ReceivePlan PlanReceives(const BsmcMatrix& S, const std::vector<std::vector<uint64_t>>& patterns,
                         const std::vector<std::vector<int32_t>>& row_ids,
                         const std::vector<int32_t>& local_of,
                         const std::vector<int32_t>& global_sizes);

// The doubles of each outgoing sub-RCS message: its blocks' values and 3
// vectors per row (b, g, diag).
std::vector<int64_t> SendSizes(const BsmcMatrix* sub, const SubRcsSendPlan& plan);

}  // namespace dba
