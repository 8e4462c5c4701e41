// `dba colmap-bundle-adjuster`; see colmap_adjuster_command.h.
#include "dba/app/colmap_adjuster_command.h"

#include <algorithm>
#include <iostream>
#include <set>
#include <map>
#include <stdexcept>

#include "dba/app/solve_command.h"
#include "dba/common/error.h"

namespace dba {
namespace {

constexpr const char* kBa = "--BundleAdjustment.";

// How one COLMAP option becomes dba's: `dba` is the dba option a value maps
// to (empty: none); a boolean maps through `when_false` / `when_true`.
struct Mapping {
  const char* dba;
  const char* help;
};

// COLMAP's options with a value (3.8's names and 3.12's), by name: --help
// lists them alphabetically.
const std::map<std::string, Mapping>& ValueOptions() {
  static const std::map<std::string, Mapping> m = {
      {"--input_path", {"", "the model to adjust (dba solve's INPUT)"}},
      {"--output_path", {"-o", "the directory the adjusted model is written to (-o)"}},
      {"--BundleAdjustment.max_num_iterations", {"--max-iterations", "default 100"}},
      {"--BundleAdjustment.max_linear_solver_iterations",
       {"--pcg-max-iterations", "when given: the PCG iteration limit (dba picks its linear solver)"}},
      {"--BundleAdjustment.function_tolerance", {"--function-tolerance", "default 0"}},
      {"--BundleAdjustment.gradient_tolerance", {"--gradient-tolerance", "default 0"}},
      {"--BundleAdjustment.parameter_tolerance", {"--parameter-tolerance", "default 0"}},
      {"--threads", {"--threads", "dba's own (not COLMAP's): threads (default: every core)"}},
  };
  return m;
}

// COLMAP's boolean options: refine (1) or hold (0) a kind of parameter.
struct Refinement {
  bool colmap_default;
  const char* hold;  // dba's option and value holding it ("" for none)
  const char* help;
};
const std::map<std::string, Refinement>& Refinements() {
  static const std::map<std::string, Refinement> m = {
      {"--BundleAdjustment.refine_focal_length", {true, "--fix-intrinsics focal", "0: --fix-intrinsics focal"}},
      {"--BundleAdjustment.refine_principal_point",
       {false, "", "1: --refine-principal-point (default 0: held, as dba's default)"}},
      {"--BundleAdjustment.refine_extra_params", {true, "--fix-intrinsics extra", "0: --fix-intrinsics extra"}},
      {"--BundleAdjustment.refine_extrinsics", {true, "--fix-images all", "0: --fix-images all"}},
      {"--BundleAdjustment.refine_rig_from_world", {true, "--fix-images all", "3.12's refine_extrinsics"}},
      {"--BundleAdjustment.refine_sensor_from_rig",
       {true, "--rig-geometry fixed", "3.12, 0: --rig-geometry fixed (the rigs' sensor poses held)"}},
  };
  return m;
}

// Options that choose how COLMAP runs, not what it computes.
const char* const kNoEffect[] = {"--random_seed", "--log_to_stderr", "--log_level",
                                 "--BundleAdjustment.use_gpu", "--BundleAdjustment.gpu_index"};

bool ParseBool(const std::string& name, const std::string& v) {
  if (v == "1" || v == "true") return true;
  if (v == "0" || v == "false") return false;
  throw UsageError(name + ": '" + Clipped(v) + "' is not a boolean (1, 0, true, false)");
}

void PrintHelp(std::ostream& out) {
  out << "Usage: dba colmap-bundle-adjuster --input_path DIR --output_path DIR [COLMAP options]\n\n"
         "A drop-in for `colmap bundle_adjuster` (COLMAP 3.8 and 3.12 option names), with\n"
         "COLMAP's defaults; each option becomes dba solve's:\n";
  for (const auto& [name, m] : ValueOptions()) out << "  " << name << " X    " << m.help << "\n";
  for (const auto& [name, r] : Refinements()) out << "  " << name << " 0|1    " << r.help << "\n";
  out << "  ";
  for (const char* n : kNoEffect) out << n << " ";
  out << "   accepted; they change how COLMAP runs, not its result\n"
         "Refused: --project_path (give the options on the command line) and any other option.\n"
         "The gauge is COLMAP's (--gauge colmap): the first image's pose and the x of the second's\n"
         "translation (the model's file order) are kept; the final cost is COLMAP's optimum's.\n";
}

}  // namespace

std::vector<std::string> SolveArgumentsOfColmap(const std::vector<std::string>& args) {
  std::map<std::string, std::string> given;
  for (size_t i = 0; i < args.size(); ++i) {
    std::string name = args[i], value;
    if (const size_t eq = name.find('='); eq != std::string::npos) {
      value = name.substr(eq + 1), name = name.substr(0, eq);
    } else if (i + 1 < args.size()) {
      value = args[++i];
    } else {
      throw UsageError(Clipped(name) + ": needs a value");
    }
    const bool known = ValueOptions().count(name) || Refinements().count(name) ||
                       std::find(std::begin(kNoEffect), std::end(kNoEffect), name) != std::end(kNoEffect);
    if (name == "--project_path") {
      throw UsageError("--project_path: project .ini files are not read; give the options on the command line");
    }
    if (!known) {
      throw UsageError(Clipped(name) + ": not an option of colmap bundle_adjuster that dba maps (see --help)");
    }
    given[name] = value;
  }
  for (const char* required : {"--input_path", "--output_path"}) {
    if (!given.count(required)) throw UsageError(std::string(required) + " is required");
  }
  std::vector<std::string> solve = {given["--input_path"]};
  for (const auto& [name, m] : ValueOptions()) {
    if (*m.dba != '\0' && given.count(name)) solve.insert(solve.end(), {m.dba, given[name]});
  }
  // COLMAP's defaults where dba's differ.
  for (const char* tolerance : {"function", "gradient", "parameter"}) {
    const std::string colmap = std::string(kBa) + tolerance + "_tolerance";
    if (!given.count(colmap)) solve.insert(solve.end(), {"--" + std::string(tolerance) + "-tolerance", "0"});
  }
  if (!given.count(std::string(kBa) + "max_num_iterations")) solve.insert(solve.end(), {"--max-iterations", "100"});
  solve.insert(solve.end(), {"--gauge", "colmap"});  // what COLMAP holds (camera/gauge_hold.h)
  std::set<std::string> holds;
  for (const auto& [name, r] : Refinements()) {
    if (!given.count(name) || ParseBool(name, given[name]) == r.colmap_default) continue;
    if (name == std::string(kBa) + "refine_principal_point") {
      solve.push_back("--refine-principal-point");
    } else if (*r.hold != '\0' && holds.insert(r.hold).second) {
      const std::string hold = r.hold;
      const size_t space = hold.find(' ');
      solve.insert(solve.end(), {hold.substr(0, space), hold.substr(space + 1)});
    }
  }
  return solve;
}

int ColmapBundleAdjusterMain(const std::vector<std::string>& args) {
  if (args.empty() || args[0] == "-h" || args[0] == "--help") {
    PrintHelp(std::cout);
    return args.empty() ? 2 : 0;
  }
  std::vector<std::string> solve;
  try {
    solve = SolveArgumentsOfColmap(args);
  } catch (const std::exception& e) {
    std::cerr << "dba colmap-bundle-adjuster: " << e.what() << "\n";
    return 2;
  }
  std::cout << "dba colmap-bundle-adjuster: dba solve";
  for (const std::string& a : solve) std::cout << " " << a;
  std::cout << "\n";
  return SolveMain(solve);
}

}  // namespace dba
