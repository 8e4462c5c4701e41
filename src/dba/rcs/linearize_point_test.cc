// A BAL point's linearization, four observations per SIMD lane set
// (camera/bal_camera_lanes.h), against one scalar call per observation,
// including points whose cameras share a slot of the rotation cache.
#include "dba/rcs/eliminate_point.h"

#include <gtest/gtest.h>

#include "dba/testing/synthetic_bal.h"

namespace dba {
namespace {

// 600 cameras: tracks of up to 7 often hold two cameras 256 apart, which
// share a slot of the rotation cache (rotation_frame_cache.h), and tracks of
// every length mod 4 leave lanes unused.
TEST(LinearizePoint, BalLanesMatchPerObservationCalls) {
  testing::SyntheticBalOptions o;
  o.num_cameras = 600;
  o.num_points = 1500;
  o.max_track = 7;
  o.rotation_perturbation = 0.01;
  o.seed = 5;
  const Problem problem = testing::MakeSyntheticBal(o).problem;
  const UnknownLayout layout(problem);
  PointSystem<BalModel> p;
  int shared_slots = 0;
  for (int64_t k = 0; k < problem.num_points(); ++k) {
    LinearizePoint(problem, layout, RobustLoss(), k, &p);
    const int64_t begin = problem.point_offsets[k];
    ASSERT_EQ(p.num_obs, problem.point_offsets[k + 1] - begin);
    for (int a = 0; a < p.num_obs; ++a) {
      const int32_t i = problem.obs_camera[begin + a];
      for (int b = 0; b < a; ++b) {
        const int32_t j = problem.obs_camera[begin + b];
        shared_slots += i != j && (i & 255) == (j & 255);
      }
      BalCameraJacobian J_c;
      PointJacobian J_p;
      const Vec2 r = BalResidualAndJacobians(problem.camera(i), problem.point(k),
                                             problem.pixel(begin + a), &J_c, &J_p);
      EXPECT_LT((p.r[a] - r).norm(), 1e-10 * (1 + r.norm()));
      EXPECT_LT((p.J_c[a] - J_c).norm(), 1e-10 * (1 + J_c.norm()));
      EXPECT_LT((p.J_p[a] - J_p).norm(), 1e-10 * (1 + J_p.norm()));
      EXPECT_EQ(p.camera_row[a], layout.camera_row(i));
    }
  }
  EXPECT_GT(shared_slots, 10);
}

}  // namespace
}  // namespace dba
