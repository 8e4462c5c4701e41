// The dba command-line program: dispatches to the subcommands.
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "dba/app/convert_command.h"
#include "dba/app/generate_command.h"
#include "dba/app/solve_command.h"
#include "dba/common/blas_threads.h"
#include "dba/io/temporary_registry.h"

namespace {

struct Command {
  const char* name;
  const char* synopsis;
  int (*main)(const std::vector<std::string>& args);
};

// One line per subcommand.
const Command kCommands[] = {
    {"solve", "solve INPUT [-o OUTPUT] [--report FILE.json]   bundle-adjust a problem",
     dba::SolveMain},
    {"convert", "convert INPUT OUTPUT                          BAL text (.txt/.bz2) <-> binary (.dba)",
     dba::ConvertMain},
    {"info", "info FILE                                     counts, track and camera statistics, RCS size",
     dba::InfoMain},
    {"generate", "generate OUTPUT [--images N] [--truth FILE]    a synthetic UAV survey with ground truth",
     dba::GenerateMain},
};

void PrintUsage(std::ostream& out) {
  out << "Usage: dba COMMAND [args]\n"
         "\n"
         "dba is a bundle adjuster: exact Levenberg-Marquardt with the reduced\n"
         "camera system in block-based sparse matrix compression (BSMC).\n"
         "\n"
         "Commands:\n";
  for (const Command& c : kCommands) out << "  " << c.synopsis << "\n";
  out << "\nRun 'dba COMMAND --help' for the options of a command.\n";
}

}  // namespace

int main(int argc, char** argv) {
  // An interrupted write leaves no temporary behind.
  dba::RemoveTemporariesOnSignals();
  dba::StopBlasThreads();
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
    PrintUsage(std::cout);
    return args.empty() ? 2 : 0;
  }
  for (const Command& c : kCommands) {
    if (args[0] == c.name) {
      return c.main(std::vector<std::string>(args.begin() + 1, args.end()));
    }
  }
  std::cerr << "dba: unknown command '" << args[0] << "'\n";
  PrintUsage(std::cerr);
  return 2;
}
