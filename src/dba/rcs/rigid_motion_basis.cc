// Rigid motions of the scene in each camera row's unknowns; see
// rigid_motion_basis.h.
#include "dba/rcs/rigid_motion_basis.h"

#include <Eigen/LU>

#include "dba/camera/pose_similarity.h"

namespace dba {

std::vector<CoarseRowBasis> RigidMotionBases(const UnknownLayout& layout, const double* x,
                                             bool with_scale) {
  auto is_pose_row = [&](int32_t r) {
    return r < layout.num_camera_rows() && (layout.block_size(r) == 9 || layout.block_size(r) == 6);
  };
  Vec3 centroid = Vec3::Zero();
  int64_t poses = 0;
  for (int32_t r = 0; r < layout.num_block_rows(); ++r) {
    if (!is_pose_row(r)) continue;
    centroid += CameraCentre(x + layout.param_offset(r));
    ++poses;
  }
  if (poses > 0) centroid /= static_cast<double>(poses);

  std::vector<CoarseRowBasis> bases(layout.num_block_rows());
  for (int32_t r = 0; r < layout.num_block_rows(); ++r) {
    if (!is_pose_row(r)) continue;
    const Vec3 omega = Eigen::Map<const Vec3>(x + layout.param_offset(r));
    const Vec3 t = Eigen::Map<const Vec3>(x + layout.param_offset(r) + 3);
    const Mat3 R = AngleAxisToRotation(omega);
    const Vec3 C = -R.transpose() * t;
    CoarseRowBasis& N = bases[r];
    N.rigid = true;
    N.A = -SO3LeftJacobian(omega).inverse() * R;
    N.B = Mat3::Identity();
    N.C = -SkewSymmetric(C - centroid);
    N.scale = with_scale;
    N.D = C - centroid;
  }
  return bases;
}

}  // namespace dba
