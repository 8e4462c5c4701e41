// Small synthetic rig problems (problem.h, docs/design.md §1.7) with a known
// ground truth, for tests: frames on a circle around a cube of points, each
// frame a rig of `sensors` cameras (the first the rig's origin, the others
// a few decimetres off it and turned by up to ±0.25 rad), each sensor its
// own RADIAL intrinsic group. Every image sees each point in front of it
// with probability 0.7 (points seen fewer than twice are dropped). With
// `missing`, sensor s > 0 did not fire in frames f with (f + s) % 4 == 3.
// Observations are exact projections plus Gaussian noise; the returned
// problem starts from perturbed frames, sensors and points.
//
// Thread safety: pure function of its arguments.
#pragma once

#include <cstdint>

#include "dba/testing/synthetic_bal.h"

namespace dba::testing {

struct SyntheticRigOptions {
  int frames = 6;
  int sensors = 2;
  int points = 40;
  bool missing = false;
  bool held_geometry = false;  // the sensor poses kSensorHeld, not refined
  double pixel_noise = 0.5;
  double perturbation = 1.0;   // scales the initial errors (0: start at the truth)
  uint32_t seed = 1;
};

SyntheticProblem MakeSyntheticRig(const SyntheticRigOptions& options);

}  // namespace dba::testing
