// Extraction of a rank's share; see rank_share.h.
#include "dba/cluster/rank_share.h"

namespace dba {

RankShare ExtractShare(const BalProblem& full, std::span<const int32_t> point_group,
                       int32_t group) {
  RankShare s;
  std::vector<int32_t> local_of(full.num_cameras(), -1);
  for (int64_t k = 0; k < full.num_points(); ++k) {
    if (point_group[k] != group) continue;
    for (int64_t o = full.point_offsets[k]; o < full.point_offsets[k + 1]; ++o) {
      local_of[full.obs_camera[o]] = 0;
    }
  }
  for (int64_t i = 0; i < full.num_cameras(); ++i) {
    if (local_of[i] < 0) continue;
    local_of[i] = static_cast<int32_t>(s.global_camera.size());
    s.global_camera.push_back(static_cast<int32_t>(i));
    s.problem.cameras.insert(s.problem.cameras.end(), full.camera(i),
                             full.camera(i) + kBalCameraSize);
  }
  s.problem.point_offsets.push_back(0);
  for (int64_t k = 0; k < full.num_points(); ++k) {
    if (point_group[k] != group) continue;
    s.global_point.push_back(k);
    s.problem.points.insert(s.problem.points.end(), full.point(k), full.point(k) + kPointSize);
    for (int64_t o = full.point_offsets[k]; o < full.point_offsets[k + 1]; ++o) {
      s.problem.obs_camera.push_back(local_of[full.obs_camera[o]]);
      s.problem.obs_pixel.push_back(full.obs_pixel[2 * o]);
      s.problem.obs_pixel.push_back(full.obs_pixel[2 * o + 1]);
    }
    s.problem.point_offsets.push_back(s.problem.num_observations());
  }
  return s;
}

}  // namespace dba
