// How close a solution is to the known ground truth of a synthetic problem
// (issue 5):
//   - reprojection RMS of the solved cameras and points against the
//     noise-free observations (pixels, per observation: sqrt(Σ|r|² / n), as
//     the solver's RMS), which for an exact solver is well below the
//     injected noise's σ√2;
//   - camera-centre and point errors after the similarity transform
//     (rotation, translation, scale; Umeyama) that best maps the solved
//     camera centres onto the true ones, since bundle adjustment fixes the
//     solution only up to such a transform.
//
// Thread safety: pure function.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dba/problem/bal_problem.h"

namespace dba {

struct GroundTruthErrors {
  double rms_to_noise_free_px = 0.0;
  double camera_centre_rms = 0.0;  // in the truth's units, after alignment
  double point_rms = 0.0;
  double similarity_scale = 1.0;
};

// `truth` is the ground-truth problem (true parameters, noise-free pixels);
// `cameras` and `points` the solved parameters in the same numbering.
GroundTruthErrors CompareWithGroundTruth(const BalProblem& truth,
                                         const std::vector<double>& cameras,
                                         const std::vector<double>& points);

// The same from a ground-truth file; a binary one is streamed (only its
// cameras and points are held), so large problems do not need twice the
// memory.
GroundTruthErrors CompareWithGroundTruthFile(const std::string& truth_path,
                                             const std::vector<double>& cameras,
                                             const std::vector<double>& points);

}  // namespace dba
