// Block rows in the order of the cameras' places; see aggregation_order.h.
#include "dba/rcs/aggregation_order.h"

#include "dba/camera/pose_similarity.h"
#include "dba/problem/point_order.h"

namespace dba {

std::vector<int32_t> AggregationOrder(const UnknownLayout& layout, const double* x) {
  const int32_t cameras = layout.num_camera_rows();
  std::vector<double> centres(static_cast<size_t>(3) * cameras);
  for (int32_t r = 0; r < cameras; ++r) {
    const Vec3 c = CameraCentre(x + layout.param_offset(r));
    for (int d = 0; d < 3; ++d) centres[3 * static_cast<size_t>(r) + d] = c[d];
  }
  std::vector<int32_t> order;
  order.reserve(static_cast<size_t>(layout.num_block_rows()));
  for (int64_t r : MortonOrder(centres)) order.push_back(static_cast<int32_t>(r));
  for (int32_t r = cameras; r < layout.num_block_rows(); ++r) order.push_back(r);
  return order;
}

}  // namespace dba
