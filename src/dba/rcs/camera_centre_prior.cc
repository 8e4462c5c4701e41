// Camera-centre prior residual and Jacobian; see camera_centre_prior.h.
#include "dba/rcs/camera_centre_prior.h"

namespace dba {

Vec3 CentrePriorResidual(const double* pose, const CameraCentrePrior& prior,
                         CentrePriorJacobian* J) {
  const Vec3 omega(pose[0], pose[1], pose[2]);
  const Mat3 R = AngleAxisToRotation(omega);
  const Vec3 C = -R.transpose() * Vec3(pose[3], pose[4], pose[5]);
  const Vec3 inv_sigma = prior.sigma.cwiseInverse();
  if (J != nullptr) {
    J->block<3, 3>(0, 0) = inv_sigma.asDiagonal() * SkewSymmetric(C) *
                           SO3LeftJacobian(omega).transpose();
    J->block<3, 3>(0, 3) = -(inv_sigma.asDiagonal() * R.transpose());
  }
  return inv_sigma.cwiseProduct(C - prior.centre);
}

}  // namespace dba
