// Where a set of images is, as a whole: the mean of their poses that the
// held gauge keeps (docs/design.md §1.6). Of the images' projection
// centres C_i and rotations R_i (world -> camera), n images:
//
//   centroid     c̄ = (1/n) Σ C_i
//   RMS spread   ρ = √((1/n) Σ |C_i − c̄|²)
//   orientation  M = P(Σ R_i), the chordal L2 mean argmin_{M ∈ SO(3)} Σ |M − R_i|²_F:
//                P(A) = U diag(1, 1, det(U Vᵀ)) Vᵀ for the SVD A = U S Vᵀ
//
// A similarity of the world X' = s Q X + T (camera/pose_similarity.h) maps a
// centre to s Q C + T and a rotation to R Qᵀ, so c̄ to s Q c̄ + T, ρ to s ρ
// and M to M Qᵀ. M is unique unless Σ R_i is singular (or has det < 0 and
// a repeated smallest singular value): orientations spread evenly over half
// turns, which no image set of one scene has.
//
// Thread safety: pure functions.
#pragma once

#include "dba/camera/pose_similarity.h"

namespace dba {

struct PoseSetMean {
  Vec3 centroid = Vec3::Zero();
  double spread = 0.0;               // ρ
  Mat3 orientation = Mat3::Identity();  // M
  bool operator==(const PoseSetMean& o) const {
    return centroid == o.centroid && spread == o.spread && orientation == o.orientation;
  }
};

// P(A): the rotation nearest A in the Frobenius norm.
Mat3 NearestRotation(const Mat3& A);

// The mean of the poses (ω[3], t[3], ...) at poses + stride * i, i < n, in
// that order (so the same poses give the same bits).
PoseSetMean MeanOfPoses(const double* poses, int64_t n, int stride);

}  // namespace dba
