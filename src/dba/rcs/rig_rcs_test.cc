// Rigs in the RCS (docs/design.md §1.7): the rows (frames, sensors beside
// the intrinsics), x ⊞ δ composing the images, the whole Jacobian in the
// frames' and sensors' steps against central differences of the residuals
// through that step, and the RCS formed point by point against the dense
// Schur complement.
#include <gtest/gtest.h>

#include "dba/camera/observation_residual.h"
#include "dba/camera/rig_pose.h"
#include "dba/rcs/back_substitute.h"
#include "dba/rcs/form_rcs.h"
#include "dba/rcs/unknown_layout.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/synthetic_rig.h"

namespace dba {
namespace {

double RelativeError(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).norm() / b.norm();
}

TEST(RigLayout, FramesAreTheCameraRowsAndSensorsJoinTheirGroups) {
  testing::SyntheticRigOptions o;
  o.frames = 4;
  o.sensors = 3;
  o.missing = true;
  Problem p = testing::MakeSyntheticRig(o).problem;
  p.fixed_cameras.assign(p.num_images(), 0);
  p.fixed_cameras[p.num_images() - 1] = 1;  // holds the last frame
  const UnknownLayout l(p);
  ASSERT_EQ(p.num_frames(), 4);
  EXPECT_EQ(l.num_camera_rows(), 3);
  // Groups: the origin's 5 intrinsics; two sensors with 5 + 6.
  EXPECT_EQ(l.num_block_rows(), 6);
  EXPECT_EQ(l.block_size(3), 5);
  EXPECT_EQ(l.block_size(4), 11);
  EXPECT_EQ(l.intrinsic_unknowns(4), 5);
  EXPECT_EQ(l.num_unknowns(), 3 * 6 + 5 + 11 + 11);
  for (int64_t i = 0; i < p.num_images(); ++i) {
    const int32_t f = p.image_frame[i];
    EXPECT_EQ(l.camera_row(i), f == 3 ? -1 : f) << "image " << i;
  }
  EXPECT_EQ(l.parameter_index(4, 5), p.sensor_offset(1));
  // Held geometry: the sensors' rows are their intrinsics alone.
  p.sensor_kind = {kRigOrigin, kSensorHeld, kSensorHeld};
  const UnknownLayout held(p);
  EXPECT_EQ(held.block_size(4), 5);
  EXPECT_EQ(held.intrinsic_unknowns(4), 5);
}

TEST(RigLayout, PlusStepsFramesAndSensorsAndComposesTheImages) {
  testing::SyntheticRigOptions o;
  o.sensors = 3;
  const Problem p = testing::MakeSyntheticRig(o).problem;
  const UnknownLayout l(p);
  std::vector<double> delta(l.num_unknowns());
  for (size_t j = 0; j < delta.size(); ++j) delta[j] = 1e-3 * std::sin(1.0 + j);
  std::vector<double> out(p.cameras.size());
  l.Plus(p.cameras.data(), delta.data(), out.data());
  CameraSide expected = p.camera_side();
  for (int64_t f = 0; f < p.num_frames(); ++f) {
    double* frame = expected.cameras.data() + p.frame_offset(f);
    PlusPose(frame, delta.data() + l.row_offset(l.camera_row(0) + f), frame);
  }
  for (int64_t g = 1; g < p.num_groups(); ++g) {
    const int32_t row = l.intrinsics_row(g);
    double* sensor = expected.cameras.data() + p.sensor_offset(g);
    PlusPose(sensor, delta.data() + l.row_offset(row) + 5, sensor);
    for (int j = 0; j < 5; ++j) expected.intrinsics(g)[j] += delta[l.row_offset(row) + j];
  }
  for (int j = 0; j < 5; ++j) expected.intrinsics(0)[j] += delta[l.row_offset(l.intrinsics_row(0)) + j];
  ComposeRigImages(&expected);
  for (size_t j = 0; j < out.size(); ++j) EXPECT_NEAR(out[j], expected.cameras[j], 1e-13) << j;
}

// The dense reference's Jacobian (the analytic chain) against central
// differences of every residual through x ⊞ (±h e_j).
TEST(RigJacobian, MatchesCentralDifferencesThroughTheStep) {
  testing::SyntheticRigOptions o;
  o.sensors = 3;
  o.missing = true;
  const Problem p = testing::MakeSyntheticRig(o).problem;
  const UnknownLayout l(p);
  const DampingBounds bounds;
  const auto dense = testing::BuildDenseNormalEquations(p, 0.0, bounds);
  const double h = 1e-6;
  double worst = 0.0;
  for (int64_t j = 0; j < l.num_unknowns(); ++j) {
    std::vector<double> plus(p.cameras.size()), minus(p.cameras.size());
    std::vector<double> delta(l.num_unknowns(), 0.0);
    delta[j] = h;
    l.Plus(p.cameras.data(), delta.data(), plus.data());
    delta[j] = -h;
    l.Plus(p.cameras.data(), delta.data(), minus.data());
    for (int64_t k = 0; k < p.num_points(); ++k) {
      for (int64_t obs = p.point_offsets[k]; obs < p.point_offsets[k + 1]; ++obs) {
        const int32_t i = p.obs_camera[obs];
        const Vec2 rp = ObservationResidual(p, plus.data(), i, p.point(k), p.pixel(obs));
        const Vec2 rm = ObservationResidual(p, minus.data(), i, p.point(k), p.pixel(obs));
        const Vec2 numeric = (rp - rm) / (2 * h);
        const Vec2 analytic = dense.J.block(2 * obs, j, 2, 1);
        worst = std::max(worst, (numeric - analytic).norm() / (1.0 + numeric.norm()));
      }
    }
  }
  EXPECT_LT(worst, 1e-5);
}

void ExpectRigRcsMatchesDense(const testing::SyntheticRigOptions& o, const char* what) {
  const Problem problem = testing::MakeSyntheticRig(o).problem;
  for (double lambda : {1e-4, 1.0}) {
    const DampingBounds bounds;
    RcsSystem sys = RcsSystem::ForProblem(problem);
    FormRcs(problem, lambda, bounds, 2, &sys);
    DampCameraBlocks(lambda, bounds, sys.camera_side_jtj_diagonal, &sys.S);
    const auto dense = testing::BuildDenseNormalEquations(problem, lambda, bounds);
    ASSERT_EQ(sys.S.num_rows(), dense.num_camera_params) << what;
    EXPECT_LT(RelativeError(testing::DenseFromBsmc(sys.S), dense.ReducedCameraMatrix()), 1e-10)
        << what << " lambda " << lambda;
    const Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(sys.b.data(), sys.b.size());
    EXPECT_LT(RelativeError(b, dense.ReducedRhs()), 1e-10) << what;
    EXPECT_NEAR(sys.cost, dense.cost, 1e-12 * dense.cost) << what;
  }
}

TEST(RigRcs, StereoRefinedMatchesDenseSchurComplement) {
  testing::SyntheticRigOptions o;
  ExpectRigRcsMatchesDense(o, "stereo");
}

TEST(RigRcs, RingWithMissingSensorsMatchesDenseSchurComplement) {
  testing::SyntheticRigOptions o;
  o.sensors = 4;
  o.missing = true;
  o.seed = 3;
  ExpectRigRcsMatchesDense(o, "ring, missing");
}

TEST(RigRcs, HeldGeometryMatchesDenseSchurComplement) {
  testing::SyntheticRigOptions o;
  o.sensors = 3;
  o.held_geometry = true;
  o.seed = 5;
  ExpectRigRcsMatchesDense(o, "held");
}

}  // namespace
}  // namespace dba
