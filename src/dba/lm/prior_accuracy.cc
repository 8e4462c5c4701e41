// Agreement of the cameras with their priors; see prior_accuracy.h.
#include "dba/lm/prior_accuracy.h"

#include <algorithm>
#include <cmath>

namespace dba {
namespace {

// The q-quantile (0 < q ≤ 1) of `v` by the nearest rank.
double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(std::ceil(q * v.size())) - 1);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

}  // namespace

PriorAccuracy MeasurePriorAccuracy(const CameraPriors& priors, const std::vector<double>& cameras,
                                   int camera_size,
                                   const std::vector<std::string>& image_names) {
  PriorAccuracy a;
  a.count = static_cast<int64_t>(priors.priors.size());
  if (a.count == 0) return a;
  std::array<double, 3> sum{}, sum_sq{};
  std::vector<double> horizontal, vertical;
  for (const CameraCentrePrior& p : priors.priors) {
    const Vec3 d = CameraCentre(cameras.data() + int64_t{camera_size} * p.image) - p.centre;
    for (int k = 0; k < 3; ++k) sum[k] += d[k], sum_sq[k] += d[k] * d[k];
    horizontal.push_back(std::hypot(d.x(), d.y()));
    vertical.push_back(std::abs(d.z()));
    if (d.cwiseQuotient(p.sigma).squaredNorm() > kPriorOutlierChi2) {
      a.flagged.push_back(p.image < static_cast<int32_t>(image_names.size())
                              ? image_names[p.image]
                              : std::to_string(p.image));
    }
  }
  const double n = static_cast<double>(a.count);
  for (int k = 0; k < 3; ++k) {
    a.mean[k] = sum[k] / n;
    a.rms[k] = std::sqrt(sum_sq[k] / n);
    a.sd[k] = std::sqrt(std::max(0.0, sum_sq[k] / n - a.mean[k] * a.mean[k]));
  }
  a.rms_3d = std::sqrt((sum_sq[0] + sum_sq[1] + sum_sq[2]) / n);
  a.ce90 = Quantile(horizontal, 0.9);
  a.le90 = Quantile(vertical, 0.9);
  return a;
}

}  // namespace dba
