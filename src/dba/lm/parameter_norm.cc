// ‖x‖ about the centroids; see parameter_norm.h.
#include "dba/lm/parameter_norm.h"

#include <cmath>

#include "dba/camera/pose_similarity.h"
#include "dba/camera/pose_step.h"

namespace dba {

double ParameterNorm(const UnknownLayout& layout, const std::vector<double>& cameras,
                     const PositionSpread& points) {
  PositionSpread centres;
  double squared = points.m2;
  for (int32_t r = 0; r < layout.num_block_rows(); ++r) {
    const double* p = cameras.data() + layout.param_offset(r);
    int j = 0;
    if (r < layout.num_camera_rows()) {
      centres.Add(CameraCentre(p));
      squared += p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
      j = kPoseSize;
    }
    for (; j < layout.block_size(r); ++j) {
      const double v = cameras[layout.parameter_index(r, j)];
      squared += v * v;
    }
  }
  return std::sqrt(squared + centres.m2);
}

}  // namespace dba
