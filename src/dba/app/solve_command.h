// `dba solve`: the arguments parsed (session/solve_options.h), then one
// solve (session/solve_outputs.h RunSolve: load, session, outputs) on this
// process or on every rank of an MPI job.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace dba {

// `dba solve ARGS...`: parses, runs, reports errors; returns the exit status
// (0 after help, 1 failure, 2 bad arguments). A solve that succeeds ends the
// process with status 0 without returning (its outputs committed, MPI
// ended, nothing freed: solve_command.cc).
int SolveMain(const std::vector<std::string>& args);
// The same, each error message passed through `said` before it is printed
// (the COLMAP drop-in names its own options for the dba options it gave).
int SolveMain(const std::vector<std::string>& args,
              const std::function<std::string(const std::string&)>& said);

}  // namespace dba
