// The centroid, RMS spread and chordal mean orientation of a set of poses;
// see pose_set_mean.h for the equations (docs/design.md §1.6).
#include "dba/camera/pose_set_mean.h"

#include <Eigen/LU>
#include <Eigen/SVD>

#include <cmath>

namespace dba {

Mat3 NearestRotation(const Mat3& A) {
  const Eigen::JacobiSVD<Mat3> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Mat3& U = svd.matrixU();
  const Mat3& V = svd.matrixV();
  const Vec3 d(1.0, 1.0, (U * V.transpose()).determinant() < 0 ? -1.0 : 1.0);
  return U * d.asDiagonal() * V.transpose();
}

PoseSetMean MeanOfPoses(const double* poses, int64_t n, int stride) {
  PoseSetMean m;
  if (n <= 0) return m;
  Mat3 sum = Mat3::Zero();
  for (int64_t i = 0; i < n; ++i) {
    const double* p = poses + stride * i;
    m.centroid += CameraCentre(p);
    sum += AngleAxisToRotation(Vec3(p[0], p[1], p[2]));
  }
  m.centroid /= static_cast<double>(n);
  double squares = 0.0;
  for (int64_t i = 0; i < n; ++i) squares += (CameraCentre(poses + stride * i) - m.centroid).squaredNorm();
  m.spread = std::sqrt(squares / static_cast<double>(n));
  m.orientation = NearestRotation(sum);
  return m;
}

}  // namespace dba
