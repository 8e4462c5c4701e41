// Camera-position prior residual and Jacobians; see camera_centre_prior.h.
#include "dba/rcs/camera_centre_prior.h"

#include "dba/camera/rotation.h"

namespace dba {

Vec3 CentrePriorResidual(const double* pose, const Vec3& lever_arm, const CameraCentrePrior& prior,
                         CentrePriorJacobian* J, LeverArmJacobian* J_a) {
  const Vec3 inv_sigma = prior.sigma.cwiseInverse();
  if (J != nullptr || J_a != nullptr) {
    const Vec3 omega(pose[0], pose[1], pose[2]);
    const Mat3 Rt = AngleAxisToRotation(omega).transpose();
    if (J != nullptr) {
      J->setZero();
      J->block<3, 3>(0, 3) = inv_sigma.asDiagonal();
      if (!lever_arm.isZero(0.0)) {
        J->block<3, 3>(0, 0) = inv_sigma.asDiagonal() * (Rt * SkewSymmetric(lever_arm) * SO3LeftJacobian(omega));
      }
    }
    if (J_a != nullptr) *J_a = inv_sigma.asDiagonal() * Rt;
  }
  return inv_sigma.cwiseProduct(AntennaPosition(pose, lever_arm) - prior.centre);
}

}  // namespace dba
