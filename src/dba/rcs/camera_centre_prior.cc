// Camera-centre prior residual and Jacobian; see camera_centre_prior.h.
#include "dba/rcs/camera_centre_prior.h"

namespace dba {

Vec3 CentrePriorResidual(const double* pose, const CameraCentrePrior& prior,
                         CentrePriorJacobian* J) {
  const Vec3 inv_sigma = prior.sigma.cwiseInverse();
  if (J != nullptr) {
    J->setZero();
    J->block<3, 3>(0, 3) = inv_sigma.asDiagonal();
  }
  return inv_sigma.cwiseProduct(CameraCentre(pose) - prior.centre);
}

}  // namespace dba
