// RCS block pattern from a visibility graph, against a hand-made answer and a
// std::set reference (including the periodic compaction).
#include "dba/rcs/rcs_pattern.h"

#include <gtest/gtest.h>

#include <random>
#include <set>

#include "dba/bsmc/bsmc_matrix.h"

namespace dba {
namespace {

TEST(RcsPattern, HandMadeGraph) {
  // Points seen by {0,3}, {3,1,0}, {2}, {4,4}, {1}.
  const std::vector<int64_t> offsets = {0, 2, 5, 6, 8, 9};
  const std::vector<int32_t> cameras = {0, 3, 3, 1, 0, 2, 4, 4, 1};
  const std::vector<uint64_t> got = RcsBlockPattern(5, offsets, cameras);
  const std::vector<uint64_t> expected = {PackBlock(0, 0), PackBlock(0, 1), PackBlock(0, 3),
                                          PackBlock(1, 1), PackBlock(1, 3), PackBlock(2, 2),
                                          PackBlock(3, 3), PackBlock(4, 4)};
  EXPECT_EQ(got, expected);
}

TEST(RcsPattern, RandomGraphMatchesSetReferenceThroughCompaction) {
  std::mt19937 rng(1);
  const int cameras = 300;
  std::vector<int64_t> offsets = {0};
  std::vector<int32_t> obs;
  std::set<uint64_t> reference;
  for (int i = 0; i < cameras; ++i) reference.insert(PackBlock(i, i));
  // About 3 million pairs pushed: past the 2^20 compaction threshold.
  for (int k = 0; k < 150000; ++k) {
    const int track = 2 + rng() % 6;
    const int base = rng() % cameras;
    for (int a = 0; a < track; ++a) obs.push_back((base + rng() % 40) % cameras);
    for (size_t a = offsets.back(); a < obs.size(); ++a) {
      for (size_t b = a + 1; b < obs.size(); ++b) {
        if (obs[a] != obs[b]) reference.insert(PackBlock(std::min(obs[a], obs[b]), std::max(obs[a], obs[b])));
      }
    }
    offsets.push_back(static_cast<int64_t>(obs.size()));
  }
  const std::vector<uint64_t> got = RcsBlockPattern(cameras, offsets, obs);
  EXPECT_EQ(got, std::vector<uint64_t>(reference.begin(), reference.end()));
}

}  // namespace
}  // namespace dba
