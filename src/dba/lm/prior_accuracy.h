// How well the adjusted cameras agree with their centre priors: the figures
// surveyors read in a block's report (OpenDroneMap's quality report, ISIS
// jigsaw's): for d = C - C_prior per prior (metres), per axis X, Y, Z the
// mean, standard deviation and RMS, the 3D RMS, CE90 (the 90th percentile
// of the horizontal error √(dx² + dy²)) and LE90 (of |dz|), and the priors
// flagged as outliers: those whose squared Mahalanobis distance |Σ⁻¹ d|²
// exceeds 16.27, the 99.9% χ² quantile for 3 degrees of freedom.
//
// Thread safety: pure function.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "dba/lm/prior_workers.h"

namespace dba {

inline constexpr double kPriorOutlierChi2 = 16.27;  // χ²₃ at 99.9%

struct PriorAccuracy {
  int64_t count = 0;
  std::array<double, 3> mean{}, sd{}, rms{};  // X, Y, Z
  double rms_3d = 0.0, ce90 = 0.0, le90 = 0.0;
  std::vector<std::string> flagged;  // names of the outliers, in prior order
  // The variance of unit weight σ0² = 2F / dof, dof = residuals - unknowns
  // (2 per observation, 3 per prior; camera-side unknowns and 3 per point),
  // F the final cost (robust: an approximation); set by the caller.
  double sigma0_squared = 0.0;
  int64_t degrees_of_freedom = 0;
};

// `name(i)`: how image i is called in messages and the report.
PriorAccuracy MeasurePriorAccuracy(const CameraPriors& priors, const std::vector<double>& cameras,
                                   int camera_size,
                                   const std::vector<std::string>& image_names);

// The figures as a text table (--accuracy-report FILE): the summary per
// axis and in 3D, CE90, LE90, σ0², then one row per prior: image, dx, dy,
// dz (m), the squared Mahalanobis distance, and whether it is flagged.
std::string PriorAccuracyTable(const PriorAccuracy& accuracy, const CameraPriors& priors,
                               const std::vector<double>& cameras, int camera_size,
                               const std::vector<std::string>& image_names);

}  // namespace dba
