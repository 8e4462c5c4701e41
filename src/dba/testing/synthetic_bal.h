// Small synthetic BAL problems with a known ground truth, for tests.
//
// Cameras sit on a circle around the origin looking at it; points fill a cube
// around the origin; each point is seen by a random subset of 2..max_track
// cameras. Observations are the exact projections of the true parameters
// plus Gaussian pixel noise; the returned problem starts from perturbed
// cameras and points.
//
// Thread safety: pure function of its arguments.
#pragma once

#include <cstdint>

#include "dba/problem/problem.h"

namespace dba::testing {

struct SyntheticBalOptions {
  int num_cameras = 6;
  int num_points = 40;
  int max_track = 4;
  double pixel_noise = 0.0;          // σ of the observation noise, pixels
  double rotation_perturbation = 0.0;  // σ added to angle-axis, radians
  double translation_perturbation = 0.0;
  double point_perturbation = 0.0;
  double intrinsics_perturbation = 0.0;  // relative σ on f, absolute on k1, k2
  uint32_t seed = 1;
};

struct SyntheticProblem {
  Problem truth;    // true parameters, noise-free observations
  Problem problem;  // perturbed parameters, noisy observations
};

SyntheticProblem MakeSyntheticBal(const SyntheticBalOptions& options);

}  // namespace dba::testing
