// `dba solve`: the arguments parsed (session/solve_options.h), then one
// solve (session/solve_outputs.h RunSolve: load, session, outputs) on this
// process or on every rank of an MPI job.
#pragma once

#include <string>
#include <vector>

namespace dba {

// `dba solve ARGS...`: parses, runs, reports errors; returns the exit status
// (0 after help, 1 failure, 2 bad arguments). A solve that succeeds ends the
// process with status 0 without returning (its outputs committed, MPI
// ended, nothing freed: solve_command.cc).
int SolveMain(const std::vector<std::string>& args);

}  // namespace dba
