// RCS block pattern from a visibility graph, against a hand-made answer and a
// std::set reference (including the periodic compaction).
#include "dba/rcs/rcs_pattern.h"

#include <gtest/gtest.h>

#include "dba/testing/synthetic_photo.h"

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

// The problem overload (built row by row) against a set of every pair of
// rows a point touches, for the photogrammetric model (camera and group
// rows) with fixed images and a fixed group.
TEST(RcsPattern, ProblemPatternMatchesSetReferenceWithGroupsAndFixings) {
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    testing::SyntheticPhotoOptions o;
    o.geometry.num_cameras = 30;
    o.geometry.num_points = 400;
    o.geometry.max_track = 6;
    o.geometry.seed = seed;
    o.num_groups = 4;
    Problem p = testing::MakeSyntheticPhoto(o).problem;
    p.fixed_cameras.assign(p.num_images(), 0);
    p.fixed_cameras[3] = p.fixed_cameras[17] = 1;
    p.fixed_intrinsics.assign(p.num_groups(), 0);
    p.fixed_intrinsics[2] = kAllIntrinsics;  // group 2 fixed: no row
    const UnknownLayout layout(p);
    std::set<uint64_t> reference;
    for (int32_t i = 0; i < layout.num_block_rows(); ++i) reference.insert(PackBlock(i, i));
    for (int64_t k = 0; k < p.num_points(); ++k) {
      std::vector<int32_t> rows;
      for (int64_t a = p.point_offsets[k]; a < p.point_offsets[k + 1]; ++a) {
        const int32_t i = p.obs_camera[a];
        if (layout.camera_row(i) >= 0) rows.push_back(layout.camera_row(i));
        const int32_t g = layout.intrinsics_row(p.camera_intrinsics[i]);
        if (g >= 0) rows.push_back(g);
      }
      for (int32_t x : rows) {
        for (int32_t y : rows) {
          if (x < y) reference.insert(PackBlock(x, y));
        }
      }
    }
    EXPECT_EQ(RcsBlockPattern(p, layout), std::vector<uint64_t>(reference.begin(), reference.end()))
        << "seed " << seed;
  }
}

}  // namespace
}  // namespace dba
