// A seam for tests of failure: named points of the distributed protocol and
// of the outputs' writing where a test may make a rank fail. The library
// only marks the points (FaultPoint); it never fails there by itself. A test
// installs a hook (SetFaultHook): the gtest suite directly, the command-line
// program from DBA_INJECT_FAULT (tools/fault_injection.cc) for the suite's
// mpirun scripts.
//
// Points (`step`, each counted from 1 per rank): read (a rank's share of a
// .dba), form (sub-RCS formation), step (back-substitution and step
// evaluation), finish (accept or drop the step), end (the final reports),
// write (rank 0's outputs after a distributed solve), covariance (the main
// rank's analyse stage, --covariance).
//
// Thread safety: set the hook before the ranks start; FaultPoint may be
// called from any thread then.
#pragma once

namespace dba {

// Called at every fault point; throwing from it is the injected failure.
using FaultHook = void (*)(int rank, const char* step, int count);

// Installs `hook` (null: none, the default).
void SetFaultHook(FaultHook hook);

// The `count`-th time rank `rank` reaches point `step`.
void FaultPoint(int rank, const char* step, int count);

}  // namespace dba
