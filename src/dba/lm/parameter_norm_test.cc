// ‖x‖ of the step-size stop (lm/parameter_norm.h) and the point spread it
// reads (rcs/position_spread.h): against direct sums, and the same wherever
// the world's origin is.
#include "dba/lm/parameter_norm.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "dba/camera/pose_similarity.h"
#include "dba/testing/synthetic_bal.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

// An ECEF-sized shift (|o| = 6.4e6 m).
const Vec3 kFarAway(4.2e6, 0.17e6, 4.8e6);

std::vector<Vec3> Positions(int n, const Vec3& origin) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-500.0, 500.0);
  std::vector<Vec3> x(n);
  for (Vec3& p : x) p = origin + Vec3(u(rng), u(rng), 0.05 * u(rng));
  return x;
}

// Σ |X - X̄|² the slow way, in long double.
double DirectM2(const std::vector<Vec3>& x) {
  long double mean[3] = {0, 0, 0};
  for (const Vec3& p : x) {
    for (int a = 0; a < 3; ++a) mean[a] += p[a];
  }
  for (long double& m : mean) m /= x.size();
  long double m2 = 0;
  for (const Vec3& p : x) {
    for (int a = 0; a < 3; ++a) m2 += (p[a] - mean[a]) * (p[a] - mean[a]);
  }
  return static_cast<double>(m2);
}

TEST(PositionSpread, OneAtATimeAndMergedInPartsIsTheSpreadAboutTheCentroid) {
  const std::vector<Vec3> x = Positions(1000, Vec3(10.0, -20.0, 30.0));
  PositionSpread whole;
  for (const Vec3& p : x) whole.Add(p);
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& p : x) centroid += p / static_cast<double>(x.size());
  const double m2 = DirectM2(x);
  EXPECT_EQ(whole.count, 1000.0);
  EXPECT_LE((whole.mean - centroid).norm(), 1e-12 * centroid.norm());
  EXPECT_NEAR(whole.m2, m2, 1e-12 * m2);

  // Parts of 0, 1, 299 and 700 positions, merged in any order.
  PositionSpread parts[4];
  for (size_t i = 0; i < x.size(); ++i) parts[i == 0 ? 1 : i < 300 ? 2 : 3].Add(x[i]);
  PositionSpread merged;
  for (const int p : {3, 0, 1, 2}) merged.Merge(parts[p]);
  EXPECT_EQ(merged.count, 1000.0);
  EXPECT_LE((merged.mean - centroid).norm(), 1e-12 * centroid.norm());
  EXPECT_NEAR(merged.m2, m2, 1e-12 * m2);
}

// 6.4e6 m from the origin Σ|X|² is 4e16 per point; the spread about the
// centroid keeps its digits.
TEST(PositionSpread, FarFromTheOriginKeepsItsDigits) {
  PositionSpread here, far;
  for (const Vec3& p : Positions(1000, Vec3::Zero())) here.Add(p);
  for (const Vec3& p : Positions(1000, kFarAway)) far.Add(p);
  EXPECT_NEAR(far.m2, here.m2, 1e-9 * here.m2);
  EXPECT_LE((far.mean - here.mean - kFarAway).norm(), 1e-6);
}

PositionSpread SpreadOf(const Problem& problem) {
  PositionSpread s;
  for (int64_t k = 0; k < problem.num_points(); ++k) s.Add(Vec3(problem.point(k)));
  return s;
}

// The world moved by o: points X + o, every camera seeing them as before.
void Move(const Vec3& o, Problem* problem) {
  Similarity shift;
  shift.translation = o;
  for (int64_t i = 0; i < problem->num_images(); ++i) MovePose(shift, problem->camera(i));
  for (int64_t k = 0; k < problem->num_points(); ++k) {
    for (int a = 0; a < 3; ++a) problem->point(k)[a] += o[a];
  }
}

Problem PhotoWithFixedParameters() {
  testing::SyntheticPhotoOptions o;
  o.geometry.num_cameras = 6;
  o.geometry.num_points = 50;
  o.geometry.rotation_perturbation = 0.01;
  o.num_groups = 2;
  Problem problem = testing::MakeSyntheticPhoto(o).problem;
  problem.fixed_cameras = {0, 0, 1, 0, 0, 0};
  problem.fixed_intrinsics = {kIntrinsicCx | kIntrinsicCy, 0};
  return problem;
}

// Free cameras: |ω|² + |C - C̄|² (+ f, k1, k2 of a BAL camera); free
// intrinsic parameters as they are; the points' spread.
double DirectNorm(const Problem& problem) {
  std::vector<Vec3> centres;
  double squared = DirectM2([&] {
    std::vector<Vec3> x;
    for (int64_t k = 0; k < problem.num_points(); ++k) x.emplace_back(problem.point(k));
    return x;
  }());
  for (int64_t i = 0; i < problem.num_images(); ++i) {
    if (problem.camera_fixed(i)) continue;
    const double* c = problem.camera(i);
    centres.push_back(CameraCentre(c));
    for (int j = 0; j < problem.camera_size(); ++j) {
      if (j < 3 || j >= 6) squared += c[j] * c[j];
    }
  }
  squared += DirectM2(centres);
  for (int64_t g = 0; g < problem.num_groups(); ++g) {
    for (int d = 0; d < kMaxIntrinsics; ++d) {
      if (problem.intrinsics_free_mask(g) & (1u << d)) {
        squared += problem.intrinsics(g)[d] * problem.intrinsics(g)[d];
      }
    }
  }
  return std::sqrt(squared);
}

TEST(ParameterNorm, IsTheFreePosesAboutTheirCentroidTheOtherFreeParametersAndThePointSpread) {
  for (const bool photo : {false, true}) {
    SCOPED_TRACE(photo ? "photo, a fixed camera and a fixed principal point" : "bal");
    const Problem problem =
        photo ? PhotoWithFixedParameters() : testing::MakeSyntheticBal({}).problem;
    const double expected = DirectNorm(problem);
    const double norm = ParameterNorm(UnknownLayout(problem), problem.cameras, SpreadOf(problem));
    EXPECT_NEAR(norm, expected, 1e-12 * expected);
    // What the fixed parameters hold counts for nothing.
    if (photo) {
      Problem moved = problem;
      moved.intrinsics(0)[1] += 100.0;
      moved.camera(2)[0] += 0.5;
      EXPECT_EQ(ParameterNorm(UnknownLayout(moved), moved.cameras, SpreadOf(moved)), norm);
    }
  }
}

TEST(ParameterNorm, IsTheSameWhereverTheOriginIs) {
  for (const bool photo : {false, true}) {
    SCOPED_TRACE(photo ? "photo" : "bal");
    const Problem here =
        photo ? PhotoWithFixedParameters() : testing::MakeSyntheticBal({}).problem;
    Problem far = here;
    Move(kFarAway, &far);
    const double a = ParameterNorm(UnknownLayout(here), here.cameras, SpreadOf(here));
    const double b = ParameterNorm(UnknownLayout(far), far.cameras, SpreadOf(far));
    EXPECT_NEAR(b, a, 1e-6 * a);
  }
}

}  // namespace
}  // namespace dba
