// The walk's point order: a permutation, the same for the same positions
// whatever their numbering, spatially compact; PermutePoints and its
// inverse give the problem back bit for bit, priors following their points.
#include "dba/problem/point_order.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

namespace dba {
namespace {

// n points on a 2D grid (z small), point k seen by cameras k % 7 and
// (k + 1) % 7, with a prior on every fifth point.
Problem Grid(int64_t side) {
  Problem p;
  p.point_offsets.push_back(0);
  for (int64_t i = 0; i < side; ++i) {
    for (int64_t j = 0; j < side; ++j) {
      const int64_t k = i * side + j;
      p.points.insert(p.points.end(), {double(i), double(j), 0.01 * double(k % 3)});
      for (int c : {int(k % 7), int((k + 1) % 7)}) {
        p.obs_camera.push_back(c);
        p.obs_pixel.insert(p.obs_pixel.end(), {double(k), double(-k)});
      }
      if (k % 5 == 0) {
        PointPrior prior;
        prior.point = k;
        prior.position[0] = double(k);
        p.point_priors.push_back(prior);
      }
      p.point_offsets.push_back(static_cast<int64_t>(p.obs_camera.size()));
    }
  }
  return p;
}

// Cameras in the order the points first observe them (one point's by the
// pixel, whatever the order of its observations), unseen ones last.
TEST(CamerasInPointOrder, FirstObservedFirstThenTheUnseen) {
  Problem p = Grid(3);  // point k sees cameras k % 7 and (k + 1) % 7: 0..7 seen, 7 cameras
  p.cameras.assign(9 * 9, 0.0);  // 9 BAL cameras: 7 and 8 seen by no point
  p.obs_pixel[0] = 5.0;  // point 0 is seen at x 5 by camera 0 and x 0 by camera 1
  const std::vector<int64_t> want{1, 0, 2, 3, 4, 5, 6, 7, 8};
  EXPECT_EQ(CamerasInPointOrder(p), want);
  std::swap(p.obs_camera[0], p.obs_camera[1]);
  std::swap(p.obs_pixel[0], p.obs_pixel[2]);
  std::swap(p.obs_pixel[1], p.obs_pixel[3]);
  EXPECT_EQ(CamerasInPointOrder(p), want);
  // Along a given order of the points: point 4 (cameras 4, 5) first.
  std::vector<int64_t> order{4, 0, 1, 2, 3, 5, 6, 7, 8};
  EXPECT_EQ(CamerasInPointOrder(p, order), (std::vector<int64_t>{4, 5, 1, 0, 2, 3, 6, 7, 8}));
}

// Poses move with their groups and fixed flags, observations name the new
// numbers, the intrinsic groups stay; the inverse gives the problem back.
TEST(PermuteCameras, MovesPosesGroupsFlagsAndObservationsAndTheInverseRestores) {
  Problem p = Grid(3);  // observations of cameras 0..6
  p.model = CameraModel::kPhoto;
  p.intrinsics_size = kPhotoIntrinsicsSize;
  for (int i = 0; i < 7; ++i) {
    for (int j = 0; j < kPhotoPoseSize; ++j) p.cameras.push_back(10.0 * i + j);
    p.camera_intrinsics.push_back(i % 2);
    p.fixed_cameras.push_back(i == 3 ? 1 : 0);
  }
  for (int g = 0; g < 2; ++g) {
    for (int j = 0; j < kPhotoIntrinsicsSize; ++j) p.cameras.push_back(1000.0 + 10.0 * g + j);
  }
  const Problem given = p;
  const std::vector<int64_t> order{3, 6, 0, 1, 5, 2, 4};
  PermuteCameras(order, &p);
  for (int64_t k = 0; k < 7; ++k) {
    EXPECT_EQ(p.camera(k)[0], given.camera(order[k])[0]);
    EXPECT_EQ(p.camera(k)[5], given.camera(order[k])[5]);
    EXPECT_EQ(p.camera_intrinsics[k], given.camera_intrinsics[order[k]]);
    EXPECT_EQ(p.fixed_cameras[k], given.fixed_cameras[order[k]]);
  }
  EXPECT_EQ(p.fixed_cameras[0], 1);
  for (int g = 0; g < 2; ++g) EXPECT_EQ(p.intrinsics(g)[0], given.intrinsics(g)[0]);
  for (int64_t o = 0; o < p.num_observations(); ++o) {
    EXPECT_EQ(order[p.obs_camera[o]], given.obs_camera[o]);
  }
  PermuteCameras(InversePermutation(order), &p);
  EXPECT_EQ(p.cameras, given.cameras);
  EXPECT_EQ(p.camera_intrinsics, given.camera_intrinsics);
  EXPECT_EQ(p.fixed_cameras, given.fixed_cameras);
  EXPECT_EQ(p.obs_camera, given.obs_camera);
}

TEST(PointOrder, IsAPermutationAndTheInverseRestoresTheProblemBitForBit) {
  const Problem given = Grid(20);
  Problem p = given;
  const std::vector<int64_t> order = SpatialPointOrder(p);
  std::vector<int64_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int64_t> identity(order.size());
  std::iota(identity.begin(), identity.end(), int64_t{0});
  ASSERT_EQ(sorted, identity);
  ASSERT_NE(order, identity);  // the grid's row order is not the curve's

  PermutePoints(order, &p);
  for (size_t k = 0; k < order.size(); ++k) {
    const int64_t g = order[k];
    EXPECT_EQ(p.points[3 * k], given.points[3 * g]);
    EXPECT_EQ(p.point_offsets[k + 1] - p.point_offsets[k], 2);
    EXPECT_EQ(p.obs_pixel[2 * p.point_offsets[k]], given.obs_pixel[2 * given.point_offsets[g]]);
    EXPECT_EQ(p.obs_camera[p.point_offsets[k] + 1], given.obs_camera[given.point_offsets[g] + 1]);
  }
  for (size_t q = 0; q + 1 < p.point_priors.size(); ++q) {
    EXPECT_LT(p.point_priors[q].point, p.point_priors[q + 1].point);  // sorted again
  }
  for (const PointPrior& prior : p.point_priors) {
    EXPECT_EQ(prior.position[0], double(order[prior.point]));  // follows its point
  }

  PermutePoints(InversePermutation(order), &p);
  EXPECT_EQ(p.points, given.points);
  EXPECT_EQ(p.point_offsets, given.point_offsets);
  EXPECT_EQ(p.obs_camera, given.obs_camera);
  EXPECT_EQ(p.obs_pixel, given.obs_pixel);
  ASSERT_EQ(p.point_priors.size(), given.point_priors.size());
  for (size_t q = 0; q < p.point_priors.size(); ++q) {
    EXPECT_EQ(p.point_priors[q].point, given.point_priors[q].point);
  }
}

TEST(PointOrder, TheSamePositionsGiveTheSameWalkWhateverTheirNumbering) {
  const Problem given = Grid(30);
  std::vector<int64_t> shuffle(given.num_points());
  std::iota(shuffle.begin(), shuffle.end(), int64_t{0});
  std::shuffle(shuffle.begin(), shuffle.end(), std::mt19937_64(7));
  Problem shuffled = given;
  PermutePoints(shuffle, &shuffled);
  const std::vector<int64_t> a = SpatialPointOrder(given), b = SpatialPointOrder(shuffled);
  for (size_t k = 0; k < a.size(); ++k) {
    // The k-th point walked is the same point (positions are distinct).
    EXPECT_EQ(shuffle[b[k]], a[k]) << k;
  }
}

TEST(PointOrder, ConsecutiveRangesAreSpatiallyCompact) {
  // A quarter of the walk covers a quarter of the grid: its bounding box is
  // far smaller than the grid's (a row-major quarter would span all of it).
  const Problem p = Grid(64);
  const std::vector<int64_t> order = SpatialPointOrder(p);
  const size_t quarter = order.size() / 4;
  double lo[2] = {1e9, 1e9}, hi[2] = {-1e9, -1e9};
  for (size_t k = 0; k < quarter; ++k) {
    for (int d = 0; d < 2; ++d) {
      lo[d] = std::min(lo[d], p.points[3 * order[k] + d]);
      hi[d] = std::max(hi[d], p.points[3 * order[k] + d]);
    }
  }
  EXPECT_LE((hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1), 0.3 * 64 * 64);
}

TEST(PointOrder, PointsFarOutAndNonFiniteOnesAreClampedNotLost) {
  Problem p = Grid(10);
  p.points[0] = 1e300;
  p.points[4] = -1e300;
  const std::vector<int64_t> order = SpatialPointOrder(p);
  std::vector<int64_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (size_t k = 0; k < sorted.size(); ++k) EXPECT_EQ(sorted[k], int64_t(k));
}

}  // namespace
}  // namespace dba

namespace dba {
namespace {

// A 40 x 40 grid of points in tiles of 5 x 5, each tile an image (64),
// each point seen by its tile's image and the next tile's: neighbours in
// space share images, as in a survey.
Problem Tiles() {
  Problem p = Grid(40);
  p.cameras.assign(64 * kBalCameraSize, 0.0);
  p.obs_camera.clear();
  for (int64_t i = 0; i < 40; ++i) {
    for (int64_t j = 0; j < 40; ++j) {
      const int c = static_cast<int>((i / 5) * 8 + j / 5);
      p.obs_camera.push_back(c);
      p.obs_camera.push_back((c + 1) % 64);
    }
  }
  return p;
}

TEST(PointOrder, AWalkIsTakenOnlyWhereTheInputsOrderIsScattered) {
  const Problem rows = Tiles();  // row by row: consecutive points share images
  EXPECT_GT(SharedCameraFraction(rows), 0.7);
  EXPECT_TRUE(PointWalk(rows).empty());
  std::vector<int64_t> shuffle(rows.num_points());
  std::iota(shuffle.begin(), shuffle.end(), int64_t{0});
  std::shuffle(shuffle.begin(), shuffle.end(), std::mt19937_64(3));
  Problem shuffled = rows;
  PermutePoints(shuffle, &shuffled);
  EXPECT_LT(SharedCameraFraction(shuffled), 0.1);
  const std::vector<int64_t> walk = PointWalk(shuffled);
  ASSERT_EQ(walk, SpatialPointOrder(shuffled));
  EXPECT_GT(SharedCameraFraction(shuffled, walk), 0.7);
  // Walked, the cameras come in the same order whichever order the points
  // came in.
  EXPECT_EQ(CamerasInPointOrder(shuffled, walk), CamerasInPointOrder(rows, SpatialPointOrder(rows)));
}

}  // namespace
}  // namespace dba
