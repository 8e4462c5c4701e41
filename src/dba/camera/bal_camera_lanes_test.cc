// The four-lane BAL kernel against the scalar one (camera/bal_camera.h).
#include "dba/camera/bal_camera_lanes.h"

#include <gtest/gtest.h>

#include <random>

#include "dba/camera/bal_camera.h"

namespace dba {
namespace {

TEST(BalCameraLanes, MatchesTheScalarKernelInEveryLane) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    double cameras[4][9], pixels[4][2];
    RotationFrame frames[4];
    const double X[3] = {u(rng), u(rng), u(rng)};
    for (int l = 0; l < 4; ++l) {
      // Rotations up to about 2 rad; the point about 4 units in front (-z).
      for (int e = 0; e < 3; ++e) cameras[l][e] = 1.2 * u(rng);
      frames[l] = MakeRotationFrame(cameras[l]);
      const Vec3 RX = frames[l].R * Vec3(X[0], X[1], X[2]);
      const Vec3 P(u(rng), u(rng), -4.0 + u(rng));
      for (int e = 0; e < 3; ++e) cameras[l][3 + e] = P[e] - RX[e];
      cameras[l][6] = 800 + 200 * u(rng), cameras[l][7] = 0.1 * u(rng),
      cameras[l][8] = 0.01 * u(rng);
      pixels[l][0] = 100 * u(rng), pixels[l][1] = 100 * u(rng);
    }
    const RotationFrame* frame[4] = {&frames[0], &frames[1], &frames[2], &frames[3]};
    const double* camera[4] = {cameras[0], cameras[1], cameras[2], cameras[3]};
    const double* pixel[4] = {pixels[0], pixels[1], pixels[2], pixels[3]};
    double r[4][2], J_c[4][18], J_p[4][6];
    double* rp[4] = {r[0], r[1], r[2], r[3]};
    double* J_cp[4] = {J_c[0], J_c[1], J_c[2], J_c[3]};
    double* J_pp[4] = {J_p[0], J_p[1], J_p[2], J_p[3]};
    BalResidualsAndJacobians(frame, camera, pixel, X, rp, J_cp, J_pp);
    for (int l = 0; l < 4; ++l) {
      BalCameraJacobian ref_J_c;
      PointJacobian ref_J_p;
      const Vec2 ref_r = BalResidualAndJacobians(frames[l], cameras[l], X, pixels[l], &ref_J_c,
                                                 &ref_J_p);
      for (int e = 0; e < 2; ++e) EXPECT_NEAR(r[l][e], ref_r[e], 1e-12 * (1 + std::abs(ref_r[e])));
      for (int e = 0; e < 18; ++e) {
        const double ref = ref_J_c.data()[e];
        EXPECT_NEAR(J_c[l][e], ref, 1e-12 * (1 + std::abs(ref))) << "lane " << l << " value " << e;
      }
      for (int e = 0; e < 6; ++e) {
        const double ref = ref_J_p.data()[e];
        EXPECT_NEAR(J_p[l][e], ref, 1e-12 * (1 + std::abs(ref))) << "lane " << l << " value " << e;
      }
    }
  }
}

}  // namespace
}  // namespace dba
