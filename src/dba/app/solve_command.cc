// `dba solve`; see solve_command.h.
#include "dba/app/solve_command.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <stdexcept>

#include "dba/problem/lens_model.h"
#include "dba/cluster/communicator.h"
#include "dba/common/error.h"
#include "dba/common/process_start.h"
#include "dba/session/solve_options.h"
#include "dba/session/solve_outputs.h"

namespace dba {
namespace {

// The end of a run whose outputs are committed (session/solve_outputs.h:
// no temporary is left) and whose summary is printed: what is left is
// handing back what the run holds (the problem's arrays, the result), which
// the kernel takes back at once when the process ends; freed block by block
// first, it only adds to the time after the report (17 ms at 100,000
// images: bench/README.md, "The report's time against the wall time"). So
// the streams are flushed, MPI ended (every rank comes here), and the
// process ends without destructors. Only the command line: Python's solve
// returns to the interpreter (python/src/module.cc).
[[noreturn]] void EndSolvedRun(Communicator* comm) {
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  comm->End();
  std::_Exit(0);
}

}  // namespace

int SolveMain(const std::vector<std::string>& args) {
  return SolveMain(args, [](const std::string& message) { return message; });
}

int SolveMain(const std::vector<std::string>& args,
              const std::function<std::string(const std::string&)>& said) {
  const Timer since_start = SinceProcessStart();
  SolveOptions options;
  try {
    if (std::find(args.begin(), args.end(), "--list-camera-models") != args.end()) {
      std::cout << "Lens models of intrinsic groups and their parameters (the names\n"
                   "--fix-intrinsics takes; COLMAP's models as COLMAP defines them):\n"
                << LensModelTable();
      return 0;
    }
    bool help = false;
    options = ParseSolveArguments(args, &help);
    if (help) {
      PrintSolveHelp(std::cout);
      return 0;
    }
  } catch (const std::exception& e) {
    std::cerr << "dba solve: " << said(e.what()) << "\n";
    return 2;
  }
  Communicator comm(nullptr, nullptr);
  try {
    const SolveResult result = RunSolve(options, &comm, std::cout, since_start);
    EndSolvedRun(&comm);
  } catch (const UsageError& e) {
    if (comm.size() > 1) comm.Abort(said(e.what()), 2);
    std::cerr << "dba solve: " << said(e.what()) << "\n";
    return 2;
  } catch (const std::exception& e) {
    if (comm.size() > 1) comm.Abort(said(e.what()));  // ends every rank
    std::cerr << "dba solve: error: " << said(e.what()) << "\n";
    return 1;
  }
}

}  // namespace dba
