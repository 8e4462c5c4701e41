// A free FOV ω started outside COLMAP's series branch; see fov_series_start.h.
#include "dba/camera/fov_series_start.h"

#include <cmath>
#include <cstdio>

#include "dba/problem/lens_model.h"

namespace dba {

std::vector<FovStartMove> StartFovOutsideSeries(CameraSide* side) {
  std::vector<FovStartMove> moves;
  if (side->model != CameraModel::kPhoto) return moves;
  const int omega = *LensModelParamIndex(LensModel::kFov, "omega");
  for (int64_t g = 0; g < side->num_groups(); ++g) {
    if (side->group_model(g) != LensModel::kFov) continue;
    if (!(side->intrinsics_free_mask(g) & (1u << omega))) continue;
    double& w = side->intrinsics(g)[omega];
    if (!(w * w < 1e-4)) continue;
    const double to = std::copysign(kFovClosedFormOmega, w);
    moves.push_back({g, w, to});
    w = to;
  }
  return moves;
}

std::string DescribeFovStartMoves(const std::vector<FovStartMove>& moves) {
  std::string s;
  for (const FovStartMove& m : moves) {
    char line[256];
    std::snprintf(line, sizeof line,
                  "FOV group %lld: omega %.17g starts at %g (outside COLMAP's series branch "
                  "|omega| < 0.01, where omega = 0 is a false minimum; docs/camera_models.md)\n",
                  static_cast<long long>(m.group), m.from, m.to);
    s += line;
  }
  return s;
}

}  // namespace dba
