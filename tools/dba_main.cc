// The dba command-line program: dispatches to the subcommands.
#include <unistd.h>

#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "dba/app/colmap_adjuster_command.h"
#include "dba/app/convert_command.h"
#include "dba/app/generate_command.h"
#include "dba/app/solve_command.h"
#include "dba/common/blas_threads.h"
#include "dba/io/temporary_registry.h"
#include "fault_injection.h"

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
    {"colmap-bundle-adjuster",
     "colmap-bundle-adjuster --input_path DIR --output_path DIR [...]\n"
     "                                                a drop-in for colmap bundle_adjuster",
     dba::ColmapBundleAdjusterMain},
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

// Before any library's constructor (the executable's .preinit_array), the
// environment libgomp reads once, when it loads (glibc sets the environment
// up again after this function, so only a new exec passes a change on;
// tools/dba_main.cc starts again at most once, for about 3 ms: the
// libraries linked, PROJ and CHOLMOD not among them, common/shared_library.h):
// libgomp's threads spin at a barrier for GOMP_SPINCOUNT rounds (300,000 by
// default, milliseconds) before they sleep: on a machine another process
// keeps busy a thread spins while its partner waits for the core, and PCG,
// with seven parallel regions per iteration, slowed 8x under three busy
// processes. Unless the user chose (GOMP_SPINCOUNT or OMP_WAIT_POLICY set):
// GOMP_SPINCOUNT=kSpinCount. 1000 rather than 10,000: under three busy
// processes PCG slowed 4.36x where formation slowed 2.79x with 10,000, 3.54x
// against 2.58x with 1000 (uavtxt-2500 shuffled); idle the same within noise
// (alternating, medians of 5-7: 0.996-1.036x on uavtxt-2500/10000 and
// problems 49, 16); passive waiting (OMP_WAIT_POLICY=passive) cost 18% idle.
// bench/README.md, bench/busy.sh. (OpenBLAS's environment under a limit on
// the address space is set when CHOLMOD loads: common/blas_threads.h.)
constexpr const char* kSpinCount = "GOMP_SPINCOUNT=1000";

bool Named(const char* entry, const char* name) {
  const size_t n = std::strlen(name);
  return std::strncmp(entry, name, n) == 0 && entry[n] == '=';
}

void StartWithTheLibrariesEnvironment(int, char** argv, char** envp) {
  static char spin[64];
  std::strncpy(spin, kSpinCount, sizeof spin - 1);
  static char* env[4096];
  size_t n = 0;
  for (char** e = envp; *e != nullptr; ++e) {
    if (Named(*e, "GOMP_SPINCOUNT") || Named(*e, "OMP_WAIT_POLICY")) return;
    if (n + 2 >= sizeof env / sizeof env[0]) return;
    env[n++] = *e;
  }
  env[n++] = spin;
  env[n] = nullptr;
  // The program's own path, not /proc/self/exe: ps and top show "dba".
  static char self[4096];
  const ssize_t len = ::readlink("/proc/self/exe", self, sizeof self - 1);
  if (len <= 0) return;
  self[len] = '\0';
  ::execve(self, argv, env);  // returns only where it failed: go on
}

}  // namespace

__attribute__((section(".preinit_array"), used)) static void (*const kLibrariesEnvironment)(
    int, char**, char**) = StartWithTheLibrariesEnvironment;

int main(int argc, char** argv) {
  // An interrupted write leaves no temporary behind.
  dba::RemoveTemporariesOnSignals();
  dba::StopBlasThreads();
  InstallFaultInjectionFromEnvironment();  // the test suite's DBA_INJECT_FAULT
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
