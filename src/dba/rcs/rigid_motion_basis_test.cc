// The similarity bases span S's gauge null space: one rigid motion or
// scaling of the scene, written in every camera row's basis, is a null
// vector of the undamped RCS (the observations do not change), for both
// camera models; the same rotation step for every camera is not (the same
// centre step is the scene's translation, camera/pose_step.h).
#include "dba/rcs/rigid_motion_basis.h"

#include <gtest/gtest.h>

#include "dba/bsmc/symmetric_multiply.h"
#include "dba/rcs/form_rcs.h"
#include "dba/testing/synthetic_bal.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

testing::SyntheticBalOptions Geometry(uint32_t seed) {
  testing::SyntheticBalOptions o;
  o.num_cameras = 8;
  o.num_points = 80;
  o.max_track = 5;
  o.pixel_noise = 1.0;
  o.rotation_perturbation = 0.05;
  o.translation_perturbation = 0.1;
  o.point_perturbation = 0.05;
  o.intrinsics_perturbation = 0.01;
  o.seed = seed;
  return o;
}

Problem PhotoProblem(uint32_t seed) {
  testing::SyntheticPhotoOptions o;
  o.geometry = Geometry(seed);
  o.num_groups = 2;
  o.focal_perturbation = 0.01;
  return testing::MakeSyntheticPhoto(o).problem;
}

// ‖S v‖ / (‖S‖_F ‖v‖) for v: the unit motion `k` (0-2 translation, 3-5
// rotation, 6 scale) in the similarity bases (`rigid`) or the same unit step
// of unknown k in every camera row; intrinsic rows 0.
double RelativeResidual(const Problem& problem, int k, bool rigid) {
  RcsSystem sys = RcsSystem::ForProblem(problem);
  FormRcs(problem, 0.0, DampingBounds{}, 1, &sys);
  const std::vector<CoarseRowBasis> bases = RigidMotionBases(sys.layout, problem.cameras.data(), true);
  const BsmcMatrix& S = sys.S;
  Eigen::VectorXd v = Eigen::VectorXd::Zero(S.num_rows());
  for (int32_t r = 0; r < sys.layout.num_camera_rows(); ++r) {
    EXPECT_TRUE(bases[r].rigid && bases[r].scale) << "camera row " << r;
    auto vr = v.segment(S.scalar_offset(r), 6);
    if (!rigid) {
      vr(k) = 1.0;
    } else if (k == 6) {
      vr.tail<3>() = bases[r].D;
    } else if (k < 3) {
      vr.tail<3>() = bases[r].B.col(k);
    } else {
      vr.head<3>() = bases[r].A.col(k - 3);
      vr.tail<3>() = bases[r].C.col(k - 3);
    }
  }
  for (int32_t r = sys.layout.num_camera_rows(); r < sys.layout.num_block_rows(); ++r) {
    EXPECT_FALSE(bases[r].rigid || bases[r].scale) << "intrinsic row " << r;
  }
  Eigen::VectorXd Sv(S.num_rows());
  SymmetricMultiplySerial(S, v.data(), Sv.data());
  double s_norm = 0.0;
  for (int64_t b = 0; b < S.num_blocks(); ++b) {
    const int32_t i = S.BlockRow(b), j = S.block_col(b);
    const int n = S.block_size(i) * S.block_size(j);
    for (int e = 0; e < n; ++e) s_norm += (i == j ? 1.0 : 2.0) * S.block_values(b)[e] * S.block_values(b)[e];
  }
  return Sv.norm() / (std::sqrt(s_norm) * v.norm());
}

TEST(RigidMotionBases, SimilarityMotionsAreNullVectorsOfTheBalRcs) {
  for (uint32_t seed = 1; seed <= 2; ++seed) {
    const Problem problem = testing::MakeSyntheticBal(Geometry(seed)).problem;
    for (int k = 0; k < 7; ++k) {
      EXPECT_LT(RelativeResidual(problem, k, true), 1e-10) << "seed " << seed << " motion " << k;
      if (k < 3) {
        EXPECT_GT(RelativeResidual(problem, k, false), 1e-4) << "seed " << seed << " unknown " << k;
      } else if (k < 6) {
        EXPECT_LT(RelativeResidual(problem, k, false), 1e-10) << "seed " << seed << " unknown " << k;
      }
    }
  }
}

TEST(RigidMotionBases, SimilarityMotionsAreNullVectorsOfThePhotoRcs) {
  for (uint32_t seed = 1; seed <= 2; ++seed) {
    const Problem problem = PhotoProblem(seed);
    for (int k = 0; k < 7; ++k) {
      EXPECT_LT(RelativeResidual(problem, k, true), 1e-10) << "seed " << seed << " motion " << k;
      if (k < 3) {
        EXPECT_GT(RelativeResidual(problem, k, false), 1e-4) << "seed " << seed << " unknown " << k;
      } else if (k < 6) {
        EXPECT_LT(RelativeResidual(problem, k, false), 1e-10) << "seed " << seed << " unknown " << k;
      }
    }
  }
}

// Without the scale column the basis has none; a translation column moved
// off by a wrong sign of D would not be a null vector.
TEST(RigidMotionBases, ScaleColumnIsOptionalAndNotATranslation) {
  const Problem problem = testing::MakeSyntheticBal(Geometry(3)).problem;
  RcsSystem sys = RcsSystem::ForProblem(problem);
  const std::vector<CoarseRowBasis> rigid = RigidMotionBases(sys.layout, problem.cameras.data(), false);
  const std::vector<CoarseRowBasis> similar = RigidMotionBases(sys.layout, problem.cameras.data(), true);
  for (int32_t r = 0; r < sys.layout.num_camera_rows(); ++r) {
    EXPECT_FALSE(rigid[r].scale) << "camera row " << r;
    EXPECT_TRUE(similar[r].scale) << "camera row " << r;
    EXPECT_TRUE(rigid[r].B.isApprox(similar[r].B)) << "camera row " << r;
  }
  // D varies from camera to camera (centres differ): no common translation.
  EXPECT_GT((similar[0].B.transpose() * similar[0].D - similar[1].B.transpose() * similar[1].D).norm(), 1e-3);
}

}  // namespace
}  // namespace dba
