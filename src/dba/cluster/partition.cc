// Point partitions; see partition.h.
#include "dba/cluster/partition.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "dba/bsmc/bsmc_matrix.h"
#include "dba/rcs/rcs_pattern.h"

namespace dba {

const char* PartitionSchemeName(PartitionScheme scheme) {
  return scheme == PartitionScheme::kEqual ? "equal" : "cameras";
}

PartitionScheme ParsePartitionScheme(const std::string& name) {
  if (name == "equal") return PartitionScheme::kEqual;
  if (name == "cameras") return PartitionScheme::kCameraLocality;
  throw std::invalid_argument("unknown partition scheme '" + name +
                              "' (expected 'equal' or 'cameras')");
}

std::vector<int32_t> CameraGraphOrder(const BalProblem& problem) {
  const int64_t n = problem.num_cameras();
  const std::vector<uint64_t> blocks =
      RcsBlockPattern(n, problem.point_offsets, problem.obs_camera);
  // Symmetric adjacency lists (CSR) from the upper-triangular block pattern.
  std::vector<int64_t> begin(n + 1, 0);
  for (uint64_t b : blocks) {
    if (PackedRow(b) != PackedCol(b)) ++begin[PackedRow(b) + 1], ++begin[PackedCol(b) + 1];
  }
  std::partial_sum(begin.begin(), begin.end(), begin.begin());
  std::vector<int32_t> adj(begin[n]);
  std::vector<int64_t> fill(begin.begin(), begin.end() - 1);
  for (uint64_t b : blocks) {
    const int32_t i = PackedRow(b), j = PackedCol(b);
    if (i != j) adj[fill[i]++] = j, adj[fill[j]++] = i;
  }
  auto degree = [&](int32_t i) { return begin[i + 1] - begin[i]; };
  std::vector<int32_t> by_degree(n);
  std::iota(by_degree.begin(), by_degree.end(), 0);
  std::stable_sort(by_degree.begin(), by_degree.end(),
                   [&](int32_t a, int32_t b) { return degree(a) < degree(b); });
  std::vector<int32_t> order;
  order.reserve(n);
  std::vector<char> seen(n, 0);
  for (int32_t start : by_degree) {
    if (seen[start]) continue;
    seen[start] = 1;
    size_t head = order.size();
    order.push_back(start);
    while (head < order.size()) {
      const int32_t i = order[head++];
      std::vector<int32_t> next;
      for (int64_t e = begin[i]; e < begin[i + 1]; ++e) {
        if (!seen[adj[e]]) seen[adj[e]] = 1, next.push_back(adj[e]);
      }
      std::stable_sort(next.begin(), next.end(),
                       [&](int32_t a, int32_t b) { return degree(a) < degree(b); });
      order.insert(order.end(), next.begin(), next.end());
    }
  }
  return order;
}

std::vector<int32_t> PartitionPoints(const BalProblem& problem, int num_groups,
                                     PartitionScheme scheme) {
  const int64_t num_points = problem.num_points();
  std::vector<int32_t> group(num_points, 0);
  if (num_groups <= 1) return group;
  if (scheme == PartitionScheme::kEqual) {
    for (int64_t k = 0; k < num_points; ++k) {
      group[k] = static_cast<int32_t>(k * num_groups / num_points);
    }
    return group;
  }
  // Position of every camera in the graph order, and its observation count.
  const std::vector<int32_t> order = CameraGraphOrder(problem);
  const int64_t n = problem.num_cameras();
  std::vector<int32_t> position(n);
  for (int64_t p = 0; p < n; ++p) position[order[p]] = static_cast<int32_t>(p);
  // Each point belongs to its first camera in the order; cut the order where
  // the observations of the points so assigned reach equal shares.
  std::vector<int32_t> first(num_points);
  std::vector<int64_t> obs_at(n, 0);
  for (int64_t k = 0; k < num_points; ++k) {
    int32_t best = std::numeric_limits<int32_t>::max();
    for (int64_t o = problem.point_offsets[k]; o < problem.point_offsets[k + 1]; ++o) {
      best = std::min(best, position[problem.obs_camera[o]]);
    }
    first[k] = best;
    obs_at[best] += problem.point_offsets[k + 1] - problem.point_offsets[k];
  }
  std::vector<int32_t> group_of_position(n);
  const int64_t total = problem.num_observations();
  int64_t done = 0;
  for (int64_t p = 0; p < n; ++p) {
    // The group whose share contains the middle of this camera's observations.
    const int64_t middle = done + obs_at[p] / 2;
    group_of_position[p] = static_cast<int32_t>(
        std::min<int64_t>(num_groups - 1, middle * num_groups / std::max<int64_t>(total, 1)));
    done += obs_at[p];
  }
  for (int64_t k = 0; k < num_points; ++k) group[k] = group_of_position[first[k]];
  return group;
}

}  // namespace dba
