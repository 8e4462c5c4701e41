// The frame the surveyed positions hold; see external_datum.h
// (docs/design.md §8).
#include "dba/precision/external_datum.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dba {

std::string FrameLeftFreeBy(const std::vector<SurveyedPosition>& positions) {
  const size_t n = positions.size();
  if (n == 0) return "";
  Vec3 mean = Vec3::Zero();
  for (const SurveyedPosition& p : positions) mean += p.position / static_cast<double>(n);
  Mat3 spread = Mat3::Zero();
  std::vector<double> sigma;
  for (const SurveyedPosition& p : positions) {
    spread += (p.position - mean) * (p.position - mean).transpose();
    sigma.push_back(p.sigma);
  }
  std::nth_element(sigma.begin(), sigma.begin() + n / 2, sigma.end());
  const double median_sigma = sigma[n / 2];
  // Ascending: the two smallest are the spread off the principal line.
  const Vec3 ev = Eigen::SelfAdjointEigenSolver<Mat3>(spread).eigenvalues().cwiseMax(0.0);
  char said[300];
  if (std::sqrt(ev[2] / n) <= 3.0 * median_sigma) {
    std::snprintf(said, sizeof said,
                  "the %zu surveyed position(s) lie within %.3g m of one place (sigma %.3g m): the "
                  "rotation and the scale are free",
                  n, std::sqrt(ev[2] / n), median_sigma);
    return said;
  }
  const double off_line = std::sqrt((ev[0] + ev[1]) / n);
  if (off_line > 3.0 * median_sigma) return "";
  std::snprintf(said, sizeof said,
                "the %zu surveyed positions lie along one line (%.3g m RMS off it, sigma %.3g m): "
                "the rotation about it is free",
                n, off_line, median_sigma);
  return said;
}

}  // namespace dba
