// Sub-RCS to global RCS aggregation; see aggregate_sub_rcs.h.
#include "dba/cluster/aggregate_sub_rcs.h"

#include <algorithm>
#include <stdexcept>

#include "dba/cluster/block_transfer.h"

namespace dba {

int64_t SubRcsMap::PackedSize(const BsmcMatrix& global) const {
  int64_t cam = 0;
  for (int32_t g : global_row) cam += global.block_size(g);
  return num_values + 3 * cam + 5;  // + cost, ‖g_p‖∞, residual sums
}

SubRcsMap MapSubRcs(std::span<const uint64_t> local_blocks,
                    std::vector<int32_t> global_row, const BsmcMatrix& global) {
  SubRcsMap map;
  map.global_block.reserve(local_blocks.size());
  for (uint64_t b : local_blocks) {
    const int32_t gi = global_row[PackedRow(b)], gj = global_row[PackedCol(b)];
    const int64_t gb = global.FindBlock(std::min(gi, gj), std::max(gi, gj));
    if (gb < 0) throw std::logic_error("MapSubRcs: sub-RCS block missing from the global RCS");
    map.global_block.push_back(gb);
    map.transposed.push_back(gi > gj ? 1 : 0);
    map.num_values += global.value_offset(gb + 1) - global.value_offset(gb);
  }
  map.global_row = std::move(global_row);
  return map;
}

GlobalRcs BuildGlobalRcs(UnknownLayout layout,
                         const std::vector<std::vector<uint64_t>>& local_patterns,
                         std::vector<std::vector<int32_t>> rows,
                         const std::function<void(const RcsSystem&)>& before_values) {
  std::vector<uint64_t> pattern;
  for (int32_t i = 0; i < layout.num_block_rows(); ++i) pattern.push_back(PackBlock(i, i));
  if (const int32_t lever = layout.lever_arm_row(); lever >= 0) {
    for (int32_t i = 0; i < layout.num_camera_rows(); ++i) pattern.push_back(PackBlock(i, lever));
  }
  for (size_t r = 0; r < local_patterns.size(); ++r) {
    for (uint64_t b : local_patterns[r]) {
      const int32_t gi = rows[r][PackedRow(b)], gj = rows[r][PackedCol(b)];
      pattern.push_back(PackBlock(std::min(gi, gj), std::max(gi, gj)));
    }
  }
  std::sort(pattern.begin(), pattern.end());
  pattern.erase(std::unique(pattern.begin(), pattern.end()), pattern.end());
  GlobalRcs global;
  global.system = RcsSystem::ForPattern(std::move(layout), pattern, false);
  std::vector<uint64_t>().swap(pattern);
  if (before_values) before_values(global.system);
  global.system.AllocateValues();
  global.maps.resize(local_patterns.size());
  for (size_t r = 0; r < local_patterns.size(); ++r) {
    if (local_patterns[r].empty()) continue;
    global.maps[r] = MapSubRcs(local_patterns[r], std::move(rows[r]), global.system.S);
  }
  return global;
}

void PackSubRcs(const RcsSystem& sub, std::vector<double>* message) {
  message->clear();
  message->reserve(sub.S.values().size() + 3 * sub.b.size() + 5);
  message->insert(message->end(), sub.S.values().begin(), sub.S.values().end());
  message->insert(message->end(), sub.b.begin(), sub.b.end());
  message->insert(message->end(), sub.camera_side_gradient.begin(), sub.camera_side_gradient.end());
  message->insert(message->end(), sub.camera_side_jtj_diagonal.begin(),
                  sub.camera_side_jtj_diagonal.end());
  message->push_back(sub.cost);
  message->push_back(sub.max_abs_point_gradient);
  message->push_back(sub.residuals.squared);
  message->push_back(sub.residuals.inlier_squared);
  message->push_back(sub.residuals.inliers);
}

void AggregateSubRcs(const SubRcsMap& map, std::span<const double> message,
                     RcsSystem* global) {
  BsmcMatrix& S = global->S;
  const double* in = message.data();
  for (size_t k = 0; k < map.global_block.size(); ++k) {
    in = AddToBlock(in, map.transposed[k] != 0, map.global_block[k], &S);
  }
  for (std::vector<double>* vec :
       {&global->b, &global->camera_side_gradient, &global->camera_side_jtj_diagonal}) {
    for (int32_t g : map.global_row) {
      const int64_t o = S.scalar_offset(g);
      for (int d = 0; d < S.block_size(g); ++d) (*vec)[o + d] += *in++;
    }
  }
  global->cost += in[0];
  global->max_abs_point_gradient = std::max(global->max_abs_point_gradient, in[1]);
  global->residuals.Add({in[2], in[3], in[4]});
}

void ClearRcs(RcsSystem* global) {
  global->S.SetZero();
  std::fill(global->b.begin(), global->b.end(), 0.0);
  std::fill(global->camera_side_gradient.begin(), global->camera_side_gradient.end(), 0.0);
  std::fill(global->camera_side_jtj_diagonal.begin(), global->camera_side_jtj_diagonal.end(), 0.0);
  global->cost = 0.0;
  global->residuals = ResidualSums();
  global->max_abs_point_gradient = 0.0;
}

std::vector<uint64_t> BlockPattern(const BsmcMatrix& m) {
  std::vector<uint64_t> blocks;
  blocks.reserve(m.num_blocks());
  for (int32_t i = 0; i < m.num_block_rows(); ++i) {
    for (int64_t b = m.row_begin(i); b < m.row_end(i); ++b) {
      blocks.push_back(PackBlock(i, m.block_col(b)));
    }
  }
  return blocks;
}

}  // namespace dba
