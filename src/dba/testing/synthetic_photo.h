// Small synthetic problems in the photogrammetric model (poses + intrinsic
// groups shared by several images), with a known ground truth, for tests.
//
// The geometry is MakeSyntheticBal's (cameras on a circle looking at a cube
// of points), turned into COLMAP's conventions (+z forward, y down, pixel
// origin at the image corner); image i belongs to intrinsic group
// i % num_groups, every group in `lens_model` (RADIAL: the paper's model;
// others start from TypicalLensParams). Observations are exact projections plus Gaussian noise;
// the returned problem starts from perturbed poses, intrinsics and points.
//
// Thread safety: pure function of its arguments.
#pragma once

#include "dba/problem/lens_model.h"
#include "dba/testing/synthetic_bal.h"

namespace dba::testing {

struct SyntheticPhotoOptions {
  SyntheticBalOptions geometry;     // cameras, points, tracks, noise, poses
  int num_groups = 2;
  double focal_perturbation = 0.0;  // relative σ on f
  double principal_perturbation = 0.0;  // σ on cx, cy, pixels
  double distortion_perturbation = 0.0; // σ on k1 (k2: a tenth); other
                                        // models: on each extra parameter,
                                        // relative to its size
  LensModel lens_model = LensModel::kRadial;
};

SyntheticProblem MakeSyntheticPhoto(const SyntheticPhotoOptions& options);

}  // namespace dba::testing
