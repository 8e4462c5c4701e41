// `dba solve`; see solve_command.h.
#include "dba/app/solve_command.h"

#include <algorithm>
#include <iostream>
#include <stdexcept>

#include "dba/problem/lens_model.h"
#include "dba/cluster/communicator.h"
#include "dba/common/error.h"
#include "dba/session/solve_options.h"
#include "dba/session/solve_outputs.h"

namespace dba {

int SolveMain(const std::vector<std::string>& args) {
  return SolveMain(args, [](const std::string& message) { return message; });
}

int SolveMain(const std::vector<std::string>& args,
              const std::function<std::string(const std::string&)>& said) {
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
    RunSolve(options, &comm, std::cout);
    return 0;
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
