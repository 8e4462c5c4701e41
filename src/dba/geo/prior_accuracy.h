// How well an adjusted block agrees with what was surveyed: the figures
// surveyors read in a block's report (OpenDroneMap's quality report, ISIS
// jigsaw's), for each set of positions — GNSS camera priors (the adjusted
// centre C against the prior), control points (the adjusted point against
// its survey) and check points (triangulated after the solve against their
// survey). For d = adjusted - surveyed (metres), per axis X, Y, Z the mean,
// standard deviation and RMS, the 3D RMS, CE90 (the 90th percentile of the
// horizontal error √(dx² + dy²)) and LE90 (of |dz|), and those flagged as
// outliers: squared Mahalanobis distance |Σ⁻¹ d|² above 16.27, the 99.9% χ²
// quantile for 3 degrees of freedom.
//
// Thread safety: pure functions.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dba/rcs/camera_centre_prior.h"

namespace dba {

inline constexpr double kPriorOutlierChi2 = 16.27;  // χ²₃ at 99.9%

// One surveyed position against its adjusted one.
struct PositionError {
  std::string name;
  Vec3 d = Vec3::Zero();      // adjusted - surveyed
  Vec3 sigma = Vec3::Ones();  // the survey's σ per axis
  double Mahalanobis2() const { return d.cwiseQuotient(sigma).squaredNorm(); }
};

struct AccuracyFigures {
  int64_t count = 0;
  std::array<double, 3> mean{}, sd{}, rms{};  // X, Y, Z
  double rms_3d = 0.0, ce90 = 0.0, le90 = 0.0;
  std::vector<std::string> flagged;  // names of the outliers, in order
};

AccuracyFigures MeasureAccuracy(const std::vector<PositionError>& errors);

// Each prior's antenna (rcs/camera_centre_prior.h, at priors.lever_arm)
// against the prior, named by image.
std::vector<PositionError> CameraPriorErrors(const CameraPriors& priors, const CameraSide& side,
                                             const std::vector<std::string>& image_names);

// The report's sets, with their figures, and the variance of unit weight
// σ0² = 2F / dof, dof = residuals - unknowns (2 per observation, 3 per
// prior and control point; camera-side unknowns and 3 per point), F the
// final cost (robust: an approximation).
struct AccuracyReport {
  struct Set {
    std::vector<PositionError> errors;
    AccuracyFigures figures;
  };
  Set gnss, control, check;
  double sigma0_squared = 0.0;
  int64_t degrees_of_freedom = 0;
  // Fills each set's figures from its errors.
  void Measure();
};

// The report as a text table (--accuracy-report FILE): per set the summary
// per axis and in 3D, CE90 and LE90, then one row per position: name, dx,
// dy, dz (m), the squared Mahalanobis distance and whether it is flagged;
// σ0² at the top.
std::string AccuracyReportTable(const AccuracyReport& report);

}  // namespace dba
