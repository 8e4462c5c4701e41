// Point partitions; see partition.h.
#include "dba/cluster/partition.h"

#include <algorithm>
#include <iterator>
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

namespace {

VisibilityStream WholeProblem(const Problem& problem) {
  return [&problem](const VisibilityChunkFn& visit) {
    visit(0, problem.point_offsets, problem.obs_camera);
  };
}

}  // namespace

std::vector<int32_t> CameraGraphOrder(const Problem& problem) {
  return CameraGraphOrder(problem.num_images(), WholeProblem(problem));
}

std::vector<int32_t> PartitionPoints(const Problem& problem, int num_groups,
                                     PartitionScheme scheme) {
  return PartitionPoints(problem.num_images(), problem.num_points(),
                         problem.num_observations(), num_groups, scheme,
                         WholeProblem(problem));
}

std::vector<int32_t> CameraGraphOrder(int64_t n, const VisibilityStream& stream) {
  // The camera graph is the off-diagonal RCS pattern: union over chunks.
  std::vector<uint64_t> blocks;
  stream([&](int64_t, std::span<const int64_t> offsets, std::span<const int32_t> cameras) {
    std::vector<int64_t> local(offsets.begin(), offsets.end());
    for (int64_t& o : local) o -= offsets[0];
    const std::vector<uint64_t> chunk = RcsBlockPattern(n, local, cameras);
    std::vector<uint64_t> merged;
    merged.reserve(blocks.size() + chunk.size());
    std::set_union(blocks.begin(), blocks.end(), chunk.begin(), chunk.end(),
                   std::back_inserter(merged));
    blocks.swap(merged);
  });
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

std::vector<int32_t> PartitionPoints(int64_t num_cameras, int64_t num_points,
                                     int64_t num_observations, int num_groups,
                                     PartitionScheme scheme,
                                     const VisibilityStream& stream) {
  std::vector<int32_t> group(num_points, 0);
  if (num_groups <= 1) return group;
  if (scheme == PartitionScheme::kEqual) {
    for (int64_t k = 0; k < num_points; ++k) {
      group[k] = static_cast<int32_t>(k * num_groups / num_points);
    }
    return group;
  }
  // Position of every camera in the graph order, and its observation count.
  const std::vector<int32_t> order = CameraGraphOrder(num_cameras, stream);
  const int64_t n = num_cameras;
  std::vector<int32_t> position(n);
  for (int64_t p = 0; p < n; ++p) position[order[p]] = static_cast<int32_t>(p);
  // Each point belongs to its first camera in the order; cut the order where
  // the observations of the points so assigned reach equal shares.
  // (`group` holds the first camera's position until the cut is known.)
  std::vector<int32_t>& first = group;
  std::vector<int64_t> obs_at(n, 0);
  stream([&](int64_t k0, std::span<const int64_t> offsets, std::span<const int32_t> cameras) {
    for (size_t k = 0; k + 1 < offsets.size(); ++k) {
      int32_t best = std::numeric_limits<int32_t>::max();
      for (int64_t o = offsets[k]; o < offsets[k + 1]; ++o) {
        best = std::min(best, position[cameras[o - offsets[0]]]);
      }
      first[k0 + k] = best;
      obs_at[best] += offsets[k + 1] - offsets[k];
    }
  });
  std::vector<int32_t> group_of_position(n);
  const int64_t total = num_observations;
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
