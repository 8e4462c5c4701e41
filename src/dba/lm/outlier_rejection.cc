// Outlier rejection between solves; see outlier_rejection.h.
#include "dba/lm/outlier_rejection.h"

#include <numeric>

#include "dba/camera/observation_residual.h"

namespace dba {

OriginalIndices OriginalIndices::Identity(const Problem& problem) {
  OriginalIndices o;
  o.observation.resize(problem.num_observations());
  std::iota(o.observation.begin(), o.observation.end(), int64_t{0});
  o.point.resize(problem.num_points());
  std::iota(o.point.begin(), o.point.end(), int64_t{0});
  return o;
}

RejectionRound DropOutliers(double max_error_px, int num_threads, Problem* problem,
                            OriginalIndices* original) {
  const int64_t num_points = problem->num_points();
  const double bound = max_error_px * max_error_px;
  std::vector<uint8_t> keep(problem->num_observations());
#pragma omp parallel for num_threads(num_threads) schedule(dynamic, 1024)
  for (int64_t k = 0; k < num_points; ++k) {
    for (int64_t o = problem->point_offsets[k]; o < problem->point_offsets[k + 1]; ++o) {
      keep[o] = ObservationResidual(*problem, problem->cameras.data(), problem->obs_camera[o],
                                    problem->point(k), problem->pixel(o))
                    .squaredNorm() <= bound;
    }
  }
  // Compact in place: points with at least 2 kept observations, in order.
  RejectionRound round;
  int64_t obs_out = 0, point_out = 0, end = 0;
  for (int64_t k = 0; k < num_points; ++k) {
    // point_offsets[k] may already hold the compacted value: the old one is
    // the previous end. point_offsets[k + 1] is still the old one.
    const int64_t begin = end;
    end = problem->point_offsets[k + 1];
    int64_t kept = 0;
    for (int64_t o = begin; o < end; ++o) kept += keep[o];
    round.observations_dropped += (end - begin) - kept;
    if (kept < 2) {
      ++round.points_dropped;
      round.observations_dropped += kept;  // a point's last observation goes with it
      continue;
    }
    for (int d = 0; d < 3; ++d) problem->points[3 * point_out + d] = problem->points[3 * k + d];
    original->point[point_out] = original->point[k];
    for (int64_t o = begin; o < end; ++o) {
      if (!keep[o]) continue;
      problem->obs_camera[obs_out] = problem->obs_camera[o];
      problem->obs_pixel[2 * obs_out] = problem->obs_pixel[2 * o];
      problem->obs_pixel[2 * obs_out + 1] = problem->obs_pixel[2 * o + 1];
      original->observation[obs_out] = original->observation[o];
      ++obs_out;
    }
    ++point_out;
    problem->point_offsets[point_out] = obs_out;
  }
  problem->points.resize(3 * point_out);
  problem->point_offsets.resize(point_out + 1);
  problem->obs_camera.resize(obs_out);
  problem->obs_pixel.resize(2 * obs_out);
  original->point.resize(point_out);
  original->observation.resize(obs_out);
  round.observations_left = obs_out;
  round.points_left = point_out;
  return round;
}

}  // namespace dba
