// Reading of BAL ("Bundle Adjustment in the Large") problem files.
//
// Format (whitespace-separated tokens; line breaks may fall anywhere):
//   num_cameras num_points num_observations
//   camera point x y            x num_observations
//   9 camera parameters         x num_cameras
//   3 point coordinates         x num_points
// The file may be plain text or bzip2-compressed (detected by content); it
// is decoded and parsed on `threads` threads (docs/design.md §4.3).
#pragma once

#include <string>

#include "dba/problem/problem.h"

namespace dba {

// Reads the BAL problem at `path`, storing observations point-major (grouped
// by point, file order within a point). Throws dba::InputError, naming file,
// line and what was expected, on any malformed input: missing or non-numeric
// tokens, non-positive counts, indices out of range, NaN/inf values, a point
// without observations, or data left after the last point coordinate.
// No geometric checks: points behind their camera are accepted.
// `threads` 0: OpenMP's count (the run's -t). The result is the same bits
// on any number of threads.
Problem ReadBal(const std::string& path, int threads = 0);

// The reference reader, token by token over the lines: ReadBal's messages
// (the same problem, on one thread; ReadBal reads with it the files its
// parallel reader does not take).
Problem ReadBalLineByLine(const std::string& path);

}  // namespace dba
