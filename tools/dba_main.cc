// The dba command-line program: dispatches to the subcommands.
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "dba/app/solve_command.h"

namespace {

void PrintUsage(std::ostream& out) {
  out << "Usage: dba COMMAND [args]\n"
         "\n"
         "dba is a bundle adjuster: exact Levenberg-Marquardt with the reduced\n"
         "camera system in block-based sparse matrix compression (BSMC).\n"
         "\n"
         "Commands:\n"
         "  solve INPUT [-o OUTPUT] [--report FILE.json]   bundle-adjust a BAL problem\n"
         "\n"
         "Run 'dba COMMAND --help' for the options of a command.\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help" || args[0] == "help") {
    PrintUsage(std::cout);
    return args.empty() ? 2 : 0;
  }
  const std::string command = args[0];
  args.erase(args.begin());
  if (command == "solve") {
    dba::SolveCommandOptions options;
    try {
      bool help = false;
      options = dba::ParseSolveArguments(args, &help);
      if (help) {
        dba::PrintSolveHelp(std::cout);
        return 0;
      }
    } catch (const std::exception& e) {
      std::cerr << "dba solve: " << e.what() << "\n";
      return 2;
    }
    try {
      return dba::RunSolveCommand(options, std::cout);
    } catch (const std::exception& e) {
      std::cerr << "dba solve: error: " << e.what() << "\n";
      return 1;
    }
  }
  std::cerr << "dba: unknown command '" << command << "'\n";
  PrintUsage(std::cerr);
  return 2;
}
