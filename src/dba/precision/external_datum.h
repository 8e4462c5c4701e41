// Whether the surveyed positions the solve is tied to (camera-centre priors,
// control points) hold the whole frame (docs/design.md §8): a similarity is
// fixed by three positions off one line. Positions along one line, within
// a few sigma of it, leave the rotation about it free; one position leaves
// the rotation and the scale. Their covariance would then invert a matrix
// that only the noise of the positions keeps from being singular.
#pragma once

#include <string>
#include <vector>

#include "dba/camera/rotation.h"

namespace dba {

struct SurveyedPosition {
  Vec3 position = Vec3::Zero();
  double sigma = 1.0;  // its largest axis sigma
};

// What the positions leave free of the frame, in words ("" when they hold
// it): fewer than two distinct positions, or every one within 3 sigma (the
// median sigma) of their least-squares line, its RMS distance off it said.
std::string FrameLeftFreeBy(const std::vector<SurveyedPosition>& positions);

}  // namespace dba
