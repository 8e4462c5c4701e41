// The dba command-line program: dispatches to the subcommands.
#include <sys/resource.h>
#include <unistd.h>

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

// Before any library's constructor (the executable's .preinit_array):
// OpenBLAS starts one thread per core when it loads, each mapping a 128 MiB
// buffer, and under a limit on the address space (ulimit -v) a refused
// buffer is retried forever, so every command hung before main. Under such
// a limit the program starts again at once with OPENBLAS_NUM_THREADS=1
// (glibc sets the environment up again after this function, so only a new
// exec passes it to OpenBLAS): then no thread starts at load, and the sparse
// factorization takes the threads that fit (common/blas_threads.h).
void OneBlasThreadUnderAddressLimit(int, char** argv, char** envp) {
  struct rlimit limit {};
  if (::getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return;
  static char one[] = "OPENBLAS_NUM_THREADS=1";
  static char* env[4096];
  size_t n = 0;
  for (char** e = envp; *e != nullptr; ++e) {
    if (std::strcmp(*e, one) == 0) return;  // started again already, or set so
    if (std::strncmp(*e, one, sizeof "OPENBLAS_NUM_THREADS=" - 1) == 0) continue;
    if (n + 2 >= sizeof env / sizeof env[0]) return;
    env[n++] = *e;
  }
  env[n++] = one;
  env[n] = nullptr;
  ::execve("/proc/self/exe", argv, env);  // returns only where it failed: go on
}

}  // namespace

__attribute__((section(".preinit_array"), used)) static void (*const kOneBlasThread)(
    int, char**, char**) = OneBlasThreadUnderAddressLimit;

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
