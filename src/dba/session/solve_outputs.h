// What a solve writes, on the main rank, after the session: its files
// checked before the input is read (CheckSolveFiles, session/run_files.h),
// and after the solve the adjusted problem (-o: BAL, .dba or a COLMAP
// model), the point cloud (--ply), the camera centres, the JSON report, all
// appearing together or not at all (io/atomic_output_file.h,
// OutputTransaction), then the printed summary.
//
// Thread safety: one caller; touches only the files the options name.
#pragma once

#include <iosfwd>

#include "dba/common/timer.h"
#include "dba/session/solve_options.h"
#include "dba/session/solve_session.h"

namespace dba {

// Every file the run reads and writes, checked before the input is read:
// -o may replace the problem it reads, --checkpoint the checkpoint --resume
// reads; any other output naming an input or another output is refused
// (UsageError), and so is an output the rule of io/output_target.h refuses.
// `input`: what options.input holds.
void CheckSolveFiles(const SolveOptions& options, const InputSource& input);

// The loaded index of each point the solve ended with (the loaded points
// alone, not the control points after them): after rejection rounds the
// kept ones, in order (--point-covariance's numbering).
std::vector<int64_t> LoadedPointIndices(const SolveResult& result);

// The outputs' kinds against the loaded input (CheckOutput), before the
// solve.
void CheckSolveOutputs(const SolveOptions& options, const SolveInput& input,
                       const Communicator& comm);

// Writes every output `options` names from `result` (a solve on `ranks`
// ranks), then the report (its total: `since_start` when it is made) and
// prints the summary to `out`.
void WriteSolveOutputs(const SolveOptions& options, int ranks, const Timer& since_start,
                       SolveResult* result, std::ostream& out);

// A whole solve as `dba solve` runs it, on every rank of `comm`: the files
// checked, the input loaded, the session run, the outputs written (main
// rank). `since_start` is the run's clock: from the process's start on the
// command line (common/process_start.h), from the call in Python; the
// report's phases add up to it. Returns the main rank's result.
SolveResult RunSolve(const SolveOptions& options, Communicator* comm, std::ostream& out,
                     const Timer& since_start);

}  // namespace dba
