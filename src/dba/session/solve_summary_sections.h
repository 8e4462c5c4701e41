// Sections of a solve's summary (session/solve_summary.cc), in files of
// their own: georeferencing and the ground truth.
#pragma once

#include <nlohmann/json.hpp>

#include "dba/geo/georeference.h"
#include "dba/session/solve_report.h"

namespace dba {

// "georeferencing", "camera_priors", "control_points", "check_points".
void GeoreferencingFigures(const GeoreferenceSummary& geo, nlohmann::ordered_json& j);
// "ground_truth".
void TruthFigures(const SolveReport& r, nlohmann::ordered_json& j);

}  // namespace dba
