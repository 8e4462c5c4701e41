// Outlier rejection between solves; see outlier_rejection.h.
#include "dba/lm/outlier_rejection.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "dba/camera/observation_residual.h"
#include "dba/camera/rotation.h"

namespace dba {

RobustLoss RejectionStartLoss(double max_error_px) {
  return RobustLoss{LossType::kCauchy, 2.0 * max_error_px};
}

OriginalIndices OriginalIndices::Identity(const Problem& problem) {
  OriginalIndices o;
  o.observation.resize(problem.num_observations());
  std::iota(o.observation.begin(), o.observation.end(), int64_t{0});
  o.point.resize(problem.num_points());
  std::iota(o.point.begin(), o.point.end(), int64_t{0});
  return o;
}

KeptObservations KeptFlags(const OriginalIndices& original, int64_t observations, int64_t points) {
  KeptObservations kept;
  kept.observation.assign(observations, 0);
  for (int64_t o : original.observation) kept.observation[o] = 1;
  kept.point.assign(points, 0);
  for (int64_t k : original.point) kept.point[k] = 1;
  return kept;
}

OriginalIndices IndicesOf(const KeptObservations& kept) {
  OriginalIndices o;
  for (size_t i = 0; i < kept.observation.size(); ++i) {
    if (kept.observation[i]) o.observation.push_back(static_cast<int64_t>(i));
  }
  for (size_t k = 0; k < kept.point.size(); ++k) {
    if (kept.point[k]) o.point.push_back(static_cast<int64_t>(k));
  }
  return o;
}

std::vector<double> CameraCentres(const Problem& problem) {
  std::vector<double> centres(3 * problem.num_images());
  for (int64_t i = 0; i < problem.num_images(); ++i) {
    const double* c = problem.camera(i);  // both models start with ω, t
    Eigen::Map<Vec3>(centres.data() + 3 * i) =
        -AngleAxisToRotation(Vec3(c[0], c[1], c[2])).transpose() * Vec3(c[3], c[4], c[5]);
  }
  return centres;
}

double MaxTriangulationAngle(const Problem& problem, const std::vector<double>& centres, int64_t k,
                             const uint8_t* keep) {
  const Vec3 X(problem.point(k));
  auto ray = [&](int64_t o) {
    return (X - Eigen::Map<const Vec3>(centres.data() + 3 * problem.obs_camera[o])).normalized();
  };
  // The smallest cosine between two unit rays is the largest angle.
  double min_cos = 1.0;
  for (int64_t a = problem.point_offsets[k]; a < problem.point_offsets[k + 1]; ++a) {
    if (!keep[a]) continue;
    const Vec3 ray_a = ray(a);
    for (int64_t b = a + 1; b < problem.point_offsets[k + 1]; ++b) {
      if (keep[b]) min_cos = std::min(min_cos, ray_a.dot(ray(b)));
    }
  }
  return std::acos(std::clamp(min_cos, -1.0, 1.0));
}

namespace {

// Keeps, in order, the points with point_kept[k] and of their observations
// those with obs_kept[o]; `original` (may be null) follows.
void Compact(const std::vector<uint8_t>& obs_kept, const std::vector<uint8_t>& point_kept,
             Problem* problem, OriginalIndices* original) {
  const int64_t num_points = problem->num_points();
  std::vector<PointPrior>& priors = problem->point_priors;
  int64_t obs_out = 0, point_out = 0, end = 0;
  size_t prior_in = 0, prior_out = 0;
  for (int64_t k = 0; k < num_points; ++k) {
    // point_offsets[k] may already hold the compacted value: the old one is
    // the previous end. point_offsets[k + 1] is still the old one.
    const int64_t begin = end;
    end = problem->point_offsets[k + 1];
    const bool has_prior = prior_in < priors.size() && priors[prior_in].point == k;
    if (has_prior) ++prior_in;
    if (!point_kept[k]) continue;
    if (has_prior) {
      priors[prior_out] = priors[prior_in - 1];
      priors[prior_out++].point = point_out;
    }
    for (int d = 0; d < 3; ++d) problem->points[3 * point_out + d] = problem->points[3 * k + d];
    if (original != nullptr) original->point[point_out] = original->point[k];
    for (int64_t o = begin; o < end; ++o) {
      if (!obs_kept[o]) continue;
      problem->obs_camera[obs_out] = problem->obs_camera[o];
      problem->obs_pixel[2 * obs_out] = problem->obs_pixel[2 * o];
      problem->obs_pixel[2 * obs_out + 1] = problem->obs_pixel[2 * o + 1];
      if (original != nullptr) original->observation[obs_out] = original->observation[o];
      ++obs_out;
    }
    problem->point_offsets[++point_out] = obs_out;
  }
  problem->points.resize(3 * point_out);
  problem->point_offsets.resize(point_out + 1);
  problem->obs_camera.resize(obs_out);
  problem->obs_pixel.resize(2 * obs_out);
  priors.resize(prior_out);
  if (original != nullptr) {
    original->point.resize(point_out);
    original->observation.resize(obs_out);
  }
}

}  // namespace

RejectionRound DropOutliers(const RejectionCriteria& criteria, int num_threads, Problem* problem,
                            OriginalIndices* original) {
  const int64_t num_points = problem->num_points();
  const double bound = criteria.max_error_px * criteria.max_error_px;
  const double min_angle = criteria.min_triangulation_angle_deg * M_PI / 180.0;
  std::vector<uint8_t> keep(problem->num_observations());
  std::vector<uint8_t> small_angle(num_points, 0), point_kept(num_points, 0);
  const std::vector<double> centres = min_angle > 0.0 ? CameraCentres(*problem) : std::vector<double>();
#pragma omp parallel for num_threads(num_threads) schedule(dynamic, 1024)
  for (int64_t k = 0; k < num_points; ++k) {
    int64_t kept = 0;
    for (int64_t o = problem->point_offsets[k]; o < problem->point_offsets[k + 1]; ++o) {
      keep[o] = ObservationResidual(*problem, problem->cameras.data(), problem->obs_camera[o],
                                    problem->point(k), problem->pixel(o))
                    .squaredNorm() <= bound;
      kept += keep[o];
    }
    if (min_angle > 0.0 && kept >= 2 && MaxTriangulationAngle(*problem, centres, k, keep.data()) < min_angle) {
      small_angle[k] = 1;
    }
    // A control point stays, whatever is left of its observations (its
    // prior holds it).
    point_kept[k] = (kept >= 2 && !small_angle[k]) || problem->point_prior(k) != nullptr;
  }
  RejectionRound round;
  round.points_dropped = num_points - std::count(point_kept.begin(), point_kept.end(), 1);
  round.points_small_angle = std::count(small_angle.begin(), small_angle.end(), 1);
  // A dropped point's last observations go with it.
  const int64_t before = problem->num_observations();
  Compact(keep, point_kept, problem, original);
  round.observations_left = problem->num_observations();
  round.observations_dropped = before - round.observations_left;
  round.points_left = problem->num_points();
  return round;
}

void KeepOnly(const KeptObservations& kept, Problem* problem) {
  Compact(kept.observation, kept.point, problem, nullptr);
}

std::vector<RejectionRound> RunRejectionRounds(
    const std::function<RejectionRound()>& drop, const std::function<void()>& solve_again,
    const std::function<void(int, const RejectionRound&)>& on_round,
    std::vector<RejectionRound> done) {
  constexpr int kMaxRounds = 5;
  constexpr double kSettled = 5e-4;  // fraction of the observations
  const auto settled = [](const RejectionRound& round) {
    const int64_t before = round.observations_left + round.observations_dropped;
    return round.observations_dropped < kSettled * static_cast<double>(before);
  };
  std::vector<RejectionRound> rounds = std::move(done);
  if (!rounds.empty()) {  // resumed inside the solve after the last round
    if (rounds.back().observations_dropped == 0) return rounds;
    solve_again();
    if (settled(rounds.back())) return rounds;
  }
  for (int r = static_cast<int>(rounds.size()) + 1; r <= kMaxRounds; ++r) {
    const RejectionRound round = drop();
    rounds.push_back(round);
    on_round(r, round);
    if (round.observations_dropped == 0) break;
    solve_again();
    if (settled(round)) break;
  }
  return rounds;
}

}  // namespace dba
