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

std::string PriorAccuracyTable(const PriorAccuracy& a, const CameraPriors& priors,
                               const std::vector<double>& cameras, int camera_size,
                               const std::vector<std::string>& image_names) {
  std::string t;
  char line[320];
  t += "# dba accuracy report: camera centres C against their GNSS priors, d = C - prior (m)\n";
  std::snprintf(line, sizeof line, "# priors %lld, flagged %zu (squared Mahalanobis distance > %.2f)\n",
                static_cast<long long>(a.count), a.flagged.size(), kPriorOutlierChi2);
  t += line;
  t += "#\n# figure        X            Y            Z            3D\n";
  std::snprintf(line, sizeof line, "# mean   %12.6f %12.6f %12.6f\n", a.mean[0], a.mean[1], a.mean[2]);
  t += line;
  std::snprintf(line, sizeof line, "# sd     %12.6f %12.6f %12.6f\n", a.sd[0], a.sd[1], a.sd[2]);
  t += line;
  std::snprintf(line, sizeof line, "# rms    %12.6f %12.6f %12.6f %12.6f\n", a.rms[0], a.rms[1],
                a.rms[2], a.rms_3d);
  t += line;
  std::snprintf(line, sizeof line, "# CE90 %.6f m, LE90 %.6f m; sigma0^2 %.6g (%lld degrees of freedom)\n#\n",
                a.ce90, a.le90, a.sigma0_squared, static_cast<long long>(a.degrees_of_freedom));
  t += line;
  t += "# image dx dy dz mahalanobis2 flagged\n";
  for (const CameraCentrePrior& p : priors.priors) {
    const Vec3 d = CameraCentre(cameras.data() + int64_t{camera_size} * p.image) - p.centre;
    const double m2 = d.cwiseQuotient(p.sigma).squaredNorm();
    const std::string name = p.image < static_cast<int32_t>(image_names.size())
                                 ? image_names[p.image]
                                 : std::to_string(p.image);
    std::snprintf(line, sizeof line, "%s %.6f %.6f %.6f %.4f %d\n", name.c_str(), d.x(), d.y(),
                  d.z(), m2, m2 > kPriorOutlierChi2 ? 1 : 0);
    t += line;
  }
  return t;
}

}  // namespace dba
