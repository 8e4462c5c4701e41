// How a problem's images are named: a COLMAP input's image names (BAL and
// .dba problems have none; their images are 0-based indices).
// Thread safety: plain data.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace dba {

// A COLMAP input's image names: the problem's images in order, and the
// model's images without observations to adjust.
struct ImageNames {
  std::vector<std::string> problem;
  std::unordered_set<std::string> others;
  // Each problem image's width and height in pixels (its COLMAP camera's).
  std::vector<std::array<uint64_t, 2>> size;
  std::unordered_map<std::string, int32_t> index;  // problem's names -> index
  std::vector<int64_t> id;  // each problem image's COLMAP image id
  // The problem's images in the order the model's images file lists them
  // (the order COLMAP registers them in: --gauge colmap).
  std::vector<int32_t> read_order;
};

}  // namespace dba
