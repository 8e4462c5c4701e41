// Control points in the solve, check points after it; see ground_control.h.
#include "dba/geo/ground_control.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "dba/camera/observation_residual.h"

namespace dba {
namespace {

using Measurements = std::vector<GroundControlPoint::Measurement>;

double Cost(const CameraSide& side, const Measurements& m, const Vec3& X) {
  double c = 0.0;
  for (const auto& a : m) {
    c += ObservationResidual(side, side.cameras.data(), a.image, X.data(), a.pixel.data())
             .squaredNorm();
  }
  return c;
}

// Levenberg–Marquardt on X alone; the Jacobian by central differences.
Triangulation Refine(const CameraSide& side, const Measurements& m, Vec3 X) {
  double cost = Cost(side, m, X), lambda = 1e-3;
  bool converged = false;
  for (int it = 0; it < 100 && !converged && std::isfinite(cost); ++it) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Vec3 g = Vec3::Zero();
    const double h = 1e-7 * (1.0 + X.norm());
    for (const auto& a : m) {
      const Vec2 r = ObservationResidual(side, side.cameras.data(), a.image, X.data(), a.pixel.data());
      Eigen::Matrix<double, 2, 3> J;
      for (int d = 0; d < 3; ++d) {
        Vec3 xp = X, xm = X;
        xp[d] += h, xm[d] -= h;
        J.col(d) = (ObservationResidual(side, side.cameras.data(), a.image, xp.data(), a.pixel.data()) -
                    ObservationResidual(side, side.cameras.data(), a.image, xm.data(), a.pixel.data())) /
                   (2 * h);
      }
      H.noalias() += J.transpose() * J;
      g.noalias() += J.transpose() * r;
    }
    // Raise λ until a step lowers the cost; none does: converged.
    converged = true;
    for (; lambda < 1e12; lambda *= 10) {
      Eigen::Matrix3d A = H;
      A.diagonal() += lambda * H.diagonal().cwiseMax(1e-12);
      const Vec3 step = A.ldlt().solve(-g);
      const double next = Cost(side, m, X + step);
      if (!(std::isfinite(next) && next < cost)) continue;
      converged = step.norm() <= 1e-12 * (1.0 + X.norm()) || cost - next <= 1e-14 * cost;
      X += step, cost = next, lambda = std::max(1e-12, lambda / 10);
      break;
    }
  }
  Triangulation t;
  t.X = X;
  t.rms_px = std::sqrt(cost / static_cast<double>(m.size()));
  t.ok = X.allFinite() && std::isfinite(cost);
  return t;
}

}  // namespace

int64_t GroundControl::CountControl() const {
  return std::count_if(points.begin(), points.end(), [](const auto& p) { return p.control; });
}

std::vector<Triangulation> TriangulateGroundControl(const Problem& problem,
                                                    const GroundControl& gcps, bool which,
                                                    bool start_at_survey) {
  if (std::none_of(gcps.points.begin(), gcps.points.end(),
                   [&](const GroundControlPoint& p) { return p.control == which; })) {
    return {};
  }
  // The measurements by image: (point, measurement) pairs.
  std::vector<std::vector<std::pair<int, int>>> by_image(problem.num_images());
  std::vector<std::vector<double>> best_d(gcps.points.size());
  std::vector<std::vector<int64_t>> best_k(gcps.points.size());
  for (size_t p = 0; p < gcps.points.size(); ++p) {
    if (gcps.points[p].control != which) continue;
    const Measurements& m = gcps.points[p].measurements;
    best_d[p].assign(m.size(), std::numeric_limits<double>::infinity());
    best_k[p].assign(m.size(), -1);
    for (size_t a = 0; a < m.size(); ++a) by_image[m[a].image].emplace_back(p, a);
  }
  // One pass over the observations: each measurement's nearest tie point.
  const bool has_observations =
      problem.point_offsets.size() == static_cast<size_t>(problem.num_points()) + 1;
  for (int64_t k = 0; has_observations && k < problem.num_points(); ++k) {
    if (problem.point_prior(k) != nullptr) continue;  // a control point itself
    for (int64_t o = problem.point_offsets[k]; o < problem.point_offsets[k + 1]; ++o) {
      for (const auto& [p, a] : by_image[problem.obs_camera[o]]) {
        const double d = (Eigen::Map<const Vec2>(problem.pixel(o)) -
                          gcps.points[p].measurements[a].pixel).squaredNorm();
        if (d < best_d[p][a]) best_d[p][a] = d, best_k[p][a] = k;
      }
    }
  }
  std::vector<Triangulation> out;
  for (size_t p = 0; p < gcps.points.size(); ++p) {
    if (gcps.points[p].control != which) continue;
    Triangulation best;
    double best_rms = std::numeric_limits<double>::infinity();
    std::vector<int64_t> starts = best_k[p];
    std::sort(starts.begin(), starts.end());
    starts.erase(std::unique(starts.begin(), starts.end()), starts.end());
    std::vector<Vec3> from;
    if (start_at_survey) from.push_back(gcps.points[p].position);
    for (int64_t k : starts) {
      if (k >= 0) from.emplace_back(problem.point(k));
    }
    for (const Vec3& X : from) {
      const Triangulation t = Refine(problem, gcps.points[p].measurements, X);
      if (t.ok && t.rms_px < best_rms) best = t, best_rms = t.rms_px;
    }
    out.push_back(best);
  }
  return out;
}

SimilarityFit AlignToControlPoints(const GroundControl& gcps,
                                   const std::vector<Triangulation>& triangulated) {
  std::vector<Vec3> from, to;
  std::vector<double> sigma;
  size_t t = 0;
  for (const GroundControlPoint& p : gcps.points) {
    if (!p.control) continue;
    const Triangulation& x = triangulated[t++];
    // A point seen once is not triangulated; it still holds the block in LM.
    if (!x.ok || p.measurements.size() < 2) continue;
    from.push_back(x.X), to.push_back(p.position), sigma.push_back(p.sigma.maxCoeff());
  }
  if (from.size() < 3) {
    throw std::invalid_argument(
        "the alignment onto the control points needs at least 3 of them measured in 2 or more "
        "images, got " + std::to_string(from.size()) + " (or give --camera-priors)");
  }
  // Before the adjustment the block is as good as the reconstruction, not
  // the survey: the inlier bound is at least 1% of the points' spread (a
  // wrong control point is off by far more).
  Vec3 mean = Vec3::Zero();
  for (const Vec3& x : to) mean += x / static_cast<double>(to.size());
  double spread = 0.0;
  for (const Vec3& x : to) spread += (x - mean).squaredNorm() / static_cast<double>(to.size());
  for (double& s : sigma) s = std::max(s, 0.01 * std::sqrt(spread));
  return FitSimilarity(from, to, sigma);
}

void AddControlPoints(const GroundControl& gcps, Problem* problem) {
  if (problem->point_offsets.empty()) problem->point_offsets.push_back(0);  // a camera side alone
  for (const GroundControlPoint& p : gcps.points) {
    if (!p.control) continue;
    PointPrior prior;
    prior.point = problem->num_points();
    for (int a = 0; a < 3; ++a) {
      prior.position[a] = p.position[a];
      prior.weight[a] = 1.0 / p.sigma[a];
    }
    problem->point_priors.push_back(prior);
    problem->points.insert(problem->points.end(), p.position.data(), p.position.data() + 3);
    for (const auto& m : p.measurements) {
      problem->obs_camera.push_back(m.image);
      problem->obs_pixel.insert(problem->obs_pixel.end(), m.pixel.data(), m.pixel.data() + 2);
    }
    problem->point_offsets.push_back(problem->num_observations());
  }
}

std::vector<double> RemoveControlPoints(int64_t count, Problem* problem) {
  const int64_t num_points = problem->num_points();
  const int64_t first = num_points - count;
  std::vector<double> adjusted(problem->points.begin() + 3 * first, problem->points.end());
  problem->points.resize(3 * first);
  if (problem->point_offsets.size() == static_cast<size_t>(num_points) + 1) {
    const int64_t obs = problem->point_offsets[first];
    problem->point_offsets.resize(first + 1);
    problem->obs_camera.resize(obs);
    problem->obs_pixel.resize(2 * obs);
  }
  std::erase_if(problem->point_priors, [&](const PointPrior& p) { return p.point >= first; });
  return adjusted;
}

}  // namespace dba
