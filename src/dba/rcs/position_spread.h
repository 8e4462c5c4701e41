// The spread of a set of 3D positions about their own centroid: count n,
// mean X̄ and M2 = Σ |X - X̄|², one position at a time (Welford) and merged
// exactly between parts (Chan, Golub & LeVeque, "Algorithms for computing
// the sample variance: analysis and recommendations", 1983):
//
//   n = n_a + n_b,   X̄ = X̄_a + (X̄_b - X̄_a) n_b / n,
//   M2 = M2_a + M2_b + |X̄_b - X̄_a|² n_a n_b / n.
//
// Where the positions sit in the world changes nothing in M2, and no sum of
// |X|² (4e13 per point in ECEF) is ever formed. LM's step-size stop measures
// the points with it (lm/parameter_norm.h).
// Thread safety: a value.
#pragma once

#include "dba/camera/rotation.h"

namespace dba {

struct PositionSpread {
  double count = 0.0;
  Vec3 mean = Vec3::Zero();
  double m2 = 0.0;

  void Add(const Vec3& x) {
    count += 1.0;
    const Vec3 d = x - mean;
    mean += d / count;
    m2 += d.dot(x - mean);
  }
  void Merge(const PositionSpread& b) {
    if (b.count == 0.0) return;
    const double n = count + b.count;
    const Vec3 d = b.mean - mean;
    m2 += b.m2 + d.squaredNorm() * count * b.count / n;
    mean += d * (b.count / n);
    count = n;
  }
};

}  // namespace dba
