// Aggregation of sub-RCSs into the global RCS (paper section 6.1): the global
// RCS is the sum of the sub-RCSs of all point groups,
//   S = Σ_r P_rᵀ S_r P_r,   b = Σ_r P_rᵀ b_r,
// where P_r maps rank r's local RCS rows (cameras, intrinsic groups) to
// global ones. The map from each
// sub-RCS block to its global block is built once (symbolic phase), so every
// iteration's aggregation is an indexed add, not a search.
//
// Thread safety: AggregateSubRcs writes the global system; one at a time.
#pragma once

#include <cstdint>
#include <span>
#include <functional>
#include <vector>

#include "dba/bsmc/bsmc_matrix.h"
#include "dba/rcs/form_rcs.h"

namespace dba {

// A sub-RCS as the main node sees it: its blocks' global ids, in the order
// of the sub-RCS's values, and its rows' global rows. A block whose rows
// come in the reverse of their global order (a walked share's cameras) is
// added transposed (cluster/block_transfer.h).
struct SubRcsMap {
  std::vector<int64_t> global_block;
  std::vector<uint8_t> transposed;  // per block
  std::vector<int32_t> global_row;
  int64_t num_values = 0;  // doubles of the sub-RCS matrix values

  // Doubles in a packed sub-system message: the matrix values, then b, g_c
  // and diag(U) (a block size per row each), then cost, max |g_p| and the
  // three residual sums.
  int64_t PackedSize(const BsmcMatrix& global) const;
};

// Maps a sub-RCS pattern (packed local blocks, sorted) to the global matrix.
// Throws std::logic_error if a block is missing from the global matrix.
SubRcsMap MapSubRcs(std::span<const uint64_t> local_blocks,
                    std::vector<int32_t> global_row, const BsmcMatrix& global);

// The global system of the main rank (symbolic phase): its pattern is every
// diagonal block plus the union of the sub-RCS patterns `local_patterns[r]`
// with their rows in global numbering `rows[r]` (an empty pattern: a rank
// that forms no sub-RCS, which gets an empty map), and, when `layout` has
// the lever arm's row, its block with every camera row (the priors' terms,
// added on the main rank: rcs/rcs_pattern.h); and each sub-RCS's map.
struct GlobalRcs {
  RcsSystem system;
  std::vector<SubRcsMap> maps;
};
// `before_values`: see RcsSystem::ForProblem.
GlobalRcs BuildGlobalRcs(UnknownLayout layout,
                         const std::vector<std::vector<uint64_t>>& local_patterns,
                         std::vector<std::vector<int32_t>> rows,
                         const std::function<void(const RcsSystem&)>& before_values = {});

// Packs a rank's system into one message: S values, b, g_c, diag(U), cost,
// max |g_p|, residual sums.
void PackSubRcs(const RcsSystem& sub, std::vector<double>* message);

// global += the packed sub-system (cost and residual sums added, max |g_p|
// maxed).
void AggregateSubRcs(const SubRcsMap& map, std::span<const double> message,
                     RcsSystem* global);

// Zeroes the global system before aggregation.
void ClearRcs(RcsSystem* global);

// The packed (row <= col) blocks of a BSMC matrix's structure.
std::vector<uint64_t> BlockPattern(const BsmcMatrix& m);

}  // namespace dba
