// RCS block pattern from the visibility graph; see rcs_pattern.h.
#include "dba/rcs/rcs_pattern.h"

#include <algorithm>

#include "dba/bsmc/bsmc_matrix.h"

namespace dba {
namespace {

void SortUnique(std::vector<uint64_t>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

}  // namespace

std::vector<uint64_t> RcsBlockPattern(int64_t num_cameras,
                                      std::span<const int64_t> point_offsets,
                                      std::span<const int32_t> obs_camera) {
  std::vector<uint64_t> blocks;
  for (int32_t i = 0; i < num_cameras; ++i) blocks.push_back(PackBlock(i, i));
  // Compact whenever the buffer has grown well past the unique set.
  size_t compact_at = 2 * blocks.size() + (size_t{1} << 20);
  const int64_t num_points = static_cast<int64_t>(point_offsets.size()) - 1;
  for (int64_t k = 0; k < num_points; ++k) {
    for (int64_t a = point_offsets[k]; a < point_offsets[k + 1]; ++a) {
      for (int64_t b = a + 1; b < point_offsets[k + 1]; ++b) {
        const int32_t i = obs_camera[a], j = obs_camera[b];
        if (i != j) blocks.push_back(i < j ? PackBlock(i, j) : PackBlock(j, i));
      }
    }
    if (blocks.size() >= compact_at) {
      SortUnique(blocks);
      compact_at = 2 * blocks.size() + (size_t{1} << 20);
    }
  }
  SortUnique(blocks);
  blocks.shrink_to_fit();
  return blocks;
}

}  // namespace dba
