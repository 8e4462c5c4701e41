// The RCS spread over the ranks, planned; see rcs_row_plan.h.
#include "dba/cluster/rcs_row_plan.h"

#include <algorithm>
#include <stdexcept>

namespace dba {

namespace {

// Each stored block (i, j) of `sub` with its global rows and its values.
template <class F>
void ForEachSubBlock(const BsmcMatrix* sub, const std::vector<int32_t>& sub_rows, F f) {
  if (sub == nullptr) return;
  for (int32_t i = 0; i < sub->num_block_rows(); ++i) {
    for (int64_t b = sub->row_begin(i); b < sub->row_end(i); ++b) {
      const int32_t j = sub->block_col(b);
      f(sub_rows[i], sub_rows[j], int64_t{sub->block_size(i)} * sub->block_size(j));
    }
  }
}

}  // namespace

std::vector<int64_t> RowValueCounts(const BsmcMatrix* sub, const std::vector<int32_t>& sub_rows,
                                    int32_t n_global) {
  std::vector<int64_t> weight(n_global, 0);
  ForEachSubBlock(sub, sub_rows, [&](int32_t gi, int32_t gj, int64_t values) {
    weight[std::min(gi, gj)] += values;
  });
  return weight;
}

std::vector<int64_t> SymmetricRowValueCounts(const BsmcMatrix* sub,
                                             const std::vector<int32_t>& sub_rows,
                                             int32_t n_global) {
  std::vector<int64_t> count(n_global, 0);
  ForEachSubBlock(sub, sub_rows, [&](int32_t gi, int32_t gj, int64_t values) {
    count[gi] += values;
    if (gj != gi) count[gj] += values;
  });
  return count;
}

std::vector<int64_t> OwnerKeys(const std::vector<int64_t>& counts, int ranks, int rank) {
  std::vector<int64_t> key(counts.size());
  for (size_t g = 0; g < counts.size(); ++g) key[g] = counts[g] * ranks + (ranks - 1 - rank);
  return key;
}

std::vector<int32_t> OwnersFromKeys(const std::vector<int64_t>& max_keys, int ranks) {
  std::vector<int32_t> owner(max_keys.size());
  for (size_t g = 0; g < max_keys.size(); ++g) {
    owner[g] = ranks - 1 - static_cast<int32_t>(max_keys[g] % ranks);
  }
  return owner;
}

void BalanceOwnerLoad(const std::vector<int64_t>& weight, const std::vector<int64_t>& forms,
                      std::vector<int32_t>* owner, const std::vector<int32_t>& order) {
  const int ranks = static_cast<int>(forms.size());
  const int32_t n = static_cast<int32_t>(owner->size());
  std::vector<int64_t> load(ranks, 0);
  int64_t total = 0;
  for (int32_t g = 0; g < n; ++g) {
    load[(*owner)[g]] += weight[g];
    total += weight[g];
  }
  std::vector<int> forming;
  for (int q = 0; q < ranks; ++q) {
    if (forms[q] != 0) forming.push_back(q);
  }
  if (forming.empty()) forming.push_back(0);
  const double mean = static_cast<double>(total) / static_cast<double>(forming.size());
  if (*std::max_element(load.begin(), load.end()) <= 1.25 * mean) return;
  int64_t sum = 0;
  for (int32_t r = 0; r < n; ++r) {
    const int32_t g = order.empty() ? r : order[r];
    const size_t k = std::min(forming.size() - 1,
                              static_cast<size_t>(static_cast<double>(sum) / mean));
    (*owner)[g] = forming[k];
    sum += weight[g];
  }
}

SubRcsSendPlan PlanSubRcsSends(const BsmcMatrix* sub, const std::vector<int32_t>& sub_rows,
                               const std::vector<int32_t>& owner, int ranks) {
  SubRcsSendPlan plan;
  plan.blocks.assign(ranks, {});
  plan.transposed.assign(ranks, {});
  plan.pattern.assign(ranks, {});
  plan.rows.assign(ranks, {});
  plan.row_ids.assign(ranks, {});
  if (sub == nullptr) return plan;
  for (int32_t i = 0; i < sub->num_block_rows(); ++i) {
    const int32_t gi = sub_rows[i];
    plan.rows[owner[gi]].push_back(i);
    plan.row_ids[owner[gi]].push_back(gi);
    for (int64_t b = sub->row_begin(i); b < sub->row_end(i); ++b) {
      const int32_t gj = sub_rows[sub->block_col(b)];
      const int q = owner[std::min(gi, gj)];
      plan.blocks[q].push_back(b);
      plan.transposed[q].push_back(gi > gj ? 1 : 0);
      plan.pattern[q].push_back(PackBlock(std::min(gi, gj), std::max(gi, gj)));
    }
  }
  return plan;
}

std::vector<int32_t> LocalRows(const std::vector<int32_t>& own,
                               const std::vector<std::vector<uint64_t>>& patterns,
                               const std::vector<int32_t>& owner, int rank) {
  std::vector<int32_t> halo;
  for (const auto& p : patterns) {
    for (uint64_t blk : p) {
      if (owner[PackedCol(blk)] != rank) halo.push_back(PackedCol(blk));
    }
  }
  std::sort(halo.begin(), halo.end());
  halo.erase(std::unique(halo.begin(), halo.end()), halo.end());
  std::vector<int32_t> local = own;
  local.insert(local.end(), halo.begin(), halo.end());
  return local;
}

std::vector<uint64_t> LocalPattern(int32_t local_rows,
                                   const std::vector<std::vector<uint64_t>>& patterns,
                                   const std::vector<int32_t>& local_of) {
  std::vector<uint64_t> pattern;
  for (int32_t l = 0; l < local_rows; ++l) pattern.push_back(PackBlock(l, l));
  for (const auto& p : patterns) {
    for (uint64_t blk : p) {
      pattern.push_back(PackBlock(local_of[PackedRow(blk)], local_of[PackedCol(blk)]));
    }
  }
  std::sort(pattern.begin(), pattern.end());
  pattern.erase(std::unique(pattern.begin(), pattern.end()), pattern.end());
  return pattern;
}

ReceivePlan PlanReceives(const BsmcMatrix& S, const std::vector<std::vector<uint64_t>>& patterns,
                         const std::vector<std::vector<int32_t>>& row_ids,
                         const std::vector<int32_t>& local_of,
                         const std::vector<int32_t>& global_sizes) {
  const size_t ranks = patterns.size();
  ReceivePlan plan;
  plan.blocks.assign(ranks, {});
  plan.rows.assign(ranks, {});
  plan.size.assign(ranks, 0);
  for (size_t p = 0; p < ranks; ++p) {
    for (uint64_t blk : patterns[p]) {
      const int64_t lb = S.FindBlock(local_of[PackedRow(blk)], local_of[PackedCol(blk)]);
      if (lb < 0) throw std::logic_error("PlanReceives: a received block is not in the pattern");
      plan.blocks[p].push_back(lb);
      plan.size[p] += S.value_offset(lb + 1) - S.value_offset(lb);
    }
    for (int32_t g : row_ids[p]) {
      plan.rows[p].push_back(local_of[g]);
      plan.size[p] += 3 * global_sizes[g];
    }
  }
  return plan;
}

std::vector<int64_t> SendSizes(const BsmcMatrix* sub, const SubRcsSendPlan& plan) {
  std::vector<int64_t> size(plan.blocks.size(), 0);
  if (sub == nullptr) return size;
  for (size_t p = 0; p < plan.blocks.size(); ++p) {
    for (int64_t b : plan.blocks[p]) size[p] += sub->value_offset(b + 1) - sub->value_offset(b);
    for (int32_t i : plan.rows[p]) size[p] += 3 * sub->block_size(i);
  }
  return size;
}

}  // namespace dba
