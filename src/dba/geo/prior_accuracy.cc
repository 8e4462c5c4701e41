// Agreement of an adjusted block with its survey; see prior_accuracy.h.
#include "dba/geo/prior_accuracy.h"

#include <algorithm>
#include <cmath>

#include "dba/camera/pose_similarity.h"

namespace dba {
namespace {

// The q-quantile (0 < q ≤ 1) of `v` by the nearest rank.
double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(std::ceil(q * v.size())) - 1);
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

void AppendSet(const char* title, const AccuracyReport::Set& set, std::string* t) {
  const AccuracyFigures& a = set.figures;
  char line[400];
  std::snprintf(line, sizeof line,
                "#\n# %s: %lld, flagged %zu (squared Mahalanobis distance > %.2f); d (m)\n", title,
                static_cast<long long>(a.count), a.flagged.size(), kPriorOutlierChi2);
  *t += line;
  *t += "# figure        X            Y            Z            3D\n";
  std::snprintf(line, sizeof line, "# mean   %12.6f %12.6f %12.6f\n", a.mean[0], a.mean[1], a.mean[2]);
  *t += line;
  std::snprintf(line, sizeof line, "# sd     %12.6f %12.6f %12.6f\n", a.sd[0], a.sd[1], a.sd[2]);
  *t += line;
  std::snprintf(line, sizeof line, "# rms    %12.6f %12.6f %12.6f %12.6f\n", a.rms[0], a.rms[1],
                a.rms[2], a.rms_3d);
  *t += line;
  std::snprintf(line, sizeof line, "# CE90 %.6f m, LE90 %.6f m\n", a.ce90, a.le90);
  *t += line;
  for (const PositionError& e : set.errors) {
    const double m2 = e.Mahalanobis2();
    std::snprintf(line, sizeof line, "%s %s %.6f %.6f %.6f %.4f %d\n", title, e.name.c_str(),
                  e.d.x(), e.d.y(), e.d.z(), m2, m2 > kPriorOutlierChi2 ? 1 : 0);
    *t += line;
  }
}

}  // namespace

AccuracyFigures MeasureAccuracy(const std::vector<PositionError>& errors) {
  AccuracyFigures a;
  a.count = static_cast<int64_t>(errors.size());
  if (a.count == 0) return a;
  std::array<double, 3> sum{}, sum_sq{};
  std::vector<double> horizontal, vertical;
  for (const PositionError& e : errors) {
    for (int k = 0; k < 3; ++k) sum[k] += e.d[k], sum_sq[k] += e.d[k] * e.d[k];
    horizontal.push_back(std::hypot(e.d.x(), e.d.y()));
    vertical.push_back(std::abs(e.d.z()));
    if (e.Mahalanobis2() > kPriorOutlierChi2) a.flagged.push_back(e.name);
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

std::vector<PositionError> CameraPriorErrors(const CameraPriors& priors, const CameraSide& side,
                                             const std::vector<std::string>& image_names) {
  std::vector<PositionError> errors;
  for (const CameraCentrePrior& p : priors.priors) {
    PositionError e;
    e.name = p.image < static_cast<int32_t>(image_names.size()) ? image_names[p.image]
                                                               : std::to_string(p.image);
    e.d = AntennaPosition(side.cameras.data() + ExposurePoseOffset(side, p.image), priors.lever_arm) -
          p.centre;
    e.sigma = p.sigma;
    errors.push_back(std::move(e));
  }
  return errors;
}

void AccuracyReport::Measure() {
  for (Set* s : {&gnss, &control, &check}) s->figures = MeasureAccuracy(s->errors);
}

std::string AccuracyReportTable(const AccuracyReport& r) {
  std::string t = "# dba accuracy report: adjusted minus surveyed positions, d (m), per set;\n"
                  "# rows: SET NAME dx dy dz mahalanobis2 flagged\n";
  char line[200];
  std::snprintf(line, sizeof line, "# sigma0^2 %.6g (%lld degrees of freedom)\n", r.sigma0_squared,
                static_cast<long long>(r.degrees_of_freedom));
  t += line;
  if (r.gnss.figures.count > 0) AppendSet("gnss", r.gnss, &t);
  if (r.control.figures.count > 0) AppendSet("control", r.control, &t);
  if (r.check.figures.count > 0) AppendSet("check", r.check, &t);
  return t;
}

}  // namespace dba
