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

// Every diagonal block, then each point's pairs of rows; `rows_of(k, rows)`
// fills the rows touched by point k (any order, repeats allowed).
template <typename RowsOf>
std::vector<uint64_t> PatternOf(int32_t num_rows, int64_t num_points, RowsOf rows_of) {
  std::vector<uint64_t> blocks;
  for (int32_t i = 0; i < num_rows; ++i) blocks.push_back(PackBlock(i, i));
  // Compact whenever the buffer has grown well past the unique set.
  size_t compact_at = 2 * blocks.size() + (size_t{1} << 20);
  std::vector<int32_t> rows;
  for (int64_t k = 0; k < num_points; ++k) {
    rows.clear();
    rows_of(k, rows);
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    for (size_t a = 0; a < rows.size(); ++a) {
      for (size_t b = a + 1; b < rows.size(); ++b) {
        blocks.push_back(PackBlock(rows[a], rows[b]));
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

}  // namespace

std::vector<uint64_t> RcsBlockPattern(int64_t num_cameras,
                                      std::span<const int64_t> point_offsets,
                                      std::span<const int32_t> obs_camera) {
  return PatternOf(static_cast<int32_t>(num_cameras),
                   static_cast<int64_t>(point_offsets.size()) - 1,
                   [&](int64_t k, std::vector<int32_t>& rows) {
                     for (int64_t a = point_offsets[k]; a < point_offsets[k + 1]; ++a) {
                       rows.push_back(obs_camera[a]);
                     }
                   });
}

std::vector<uint64_t> RcsBlockPattern(const Problem& problem, const UnknownLayout& layout) {
  const bool photo = problem.model == CameraModel::kPhoto;
  return PatternOf(layout.num_block_rows(), problem.num_points(),
                   [&](int64_t k, std::vector<int32_t>& rows) {
                     for (int64_t a = problem.point_offsets[k]; a < problem.point_offsets[k + 1];
                          ++a) {
                       const int32_t i = problem.obs_camera[a];
                       if (layout.camera_row(i) >= 0) rows.push_back(layout.camera_row(i));
                       if (photo) {
                         const int32_t g = layout.intrinsics_row(problem.camera_intrinsics[i]);
                         if (g >= 0) rows.push_back(g);
                       }
                     }
                   });
}

}  // namespace dba
