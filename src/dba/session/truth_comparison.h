// A solve against the ground truth of a generated problem (dba generate
// --truth): the file checked before the solve, and after it the figures of
// synthetic/ground_truth.h and, with outlier rejection, how many of the
// generator's mismatches and of the true inliers were dropped.
//
// Thread safety: functions touch only the files they name.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dba/lm/outlier_rejection.h"
#include "dba/problem/problem.h"
#include "dba/session/solve_report.h"

namespace dba {

// The truth at `path` must exist and have the problem's counts (the
// report's); UsageError naming both counts otherwise. Reads its header only.
void CheckTruthFile(const std::string& path, const SolveReport& report);

// The generator's mismatches among the loaded observations (their pixels
// `loaded_pixels`, the truth's order) and how many of them and of the true
// inliers are not `kept`.
void CountTrueOutliers(const Problem& truth, const std::vector<double>& loaded_pixels,
                       const std::vector<uint8_t>& kept, SolveReport* report);

}  // namespace dba
