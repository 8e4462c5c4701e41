// `dba colmap-bundle-adjuster`; see colmap_adjuster_command.h.
#include "dba/app/colmap_adjuster_command.h"

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "dba/app/colmap_values.h"
#include "dba/app/solve_command.h"
#include "dba/common/error.h"
#include "dba/common/option_table.h"
#include "dba/io/colmap_model.h"
#include "dba/session/solve_option_table.h"

namespace dba {
namespace {

// The kind of value COLMAP 3.8 parses an option's as (boost::program_options
// and boost::lexical_cast), and its name in --help.
enum class Kind { kHelp, kRefused, kPath, kInt, kReal, kBool, kText };
constexpr const char* kValueNames[] = {"", "", " DIR", " N", " X", " 0|1", " TEXT"};

struct ColmapOption {
  const char* name;
  Kind kind;
  // dba solve's option taking the value ("" none: no effect); a boolean:
  // dba solve's arguments when the value is not `colmap_default`.
  const char* dba;
  // COLMAP's default, given to dba solve when the option is not ("" none);
  // a boolean's "1" or "0".
  const char* colmap_default;
  const char* note;  // for --help
};

constexpr const char* kNoEffect = "checked as COLMAP checks it; no effect on the result";

// colmap bundle_adjuster's options, 3.8's names and 3.12's (and dba's
// --threads), in --help's order.
const std::vector<ColmapOption>& Options() {
  static const std::vector<ColmapOption> t = {
      {"--help", Kind::kHelp, "", "", "this help (also -h)"},
      {"--project_path", Kind::kRefused, "", "",
       "refused: project .ini files are not read; give the options on the command line"},
      {"--input_path", Kind::kPath, "", "", "the model directory to adjust (dba solve's INPUT)"},
      {"--output_path", Kind::kPath, "-o", "",
       "with --colmap-format binary: written in COLMAP 3.8's format whatever the input's; "
       "the directory is made when missing"},
      {"--BundleAdjustment.max_num_iterations", Kind::kInt, "--max-iterations", "100", ""},
      {"--BundleAdjustment.max_linear_solver_iterations", Kind::kInt, "--pcg-max-iterations", "",
       "when given (dba picks its linear solver)"},
      {"--BundleAdjustment.function_tolerance", Kind::kReal, "--function-tolerance", "0", ""},
      {"--BundleAdjustment.gradient_tolerance", Kind::kReal, "--gradient-tolerance", "0", ""},
      {"--BundleAdjustment.parameter_tolerance", Kind::kReal, "--parameter-tolerance", "0", ""},
      {"--BundleAdjustment.refine_focal_length", Kind::kBool, "--fix-intrinsics focal", "1", ""},
      {"--BundleAdjustment.refine_principal_point", Kind::kBool, "--refine-principal-point", "0", ""},
      {"--BundleAdjustment.refine_extra_params", Kind::kBool, "--fix-intrinsics extra", "1", ""},
      {"--BundleAdjustment.refine_extrinsics", Kind::kBool, "--fix-images all", "1", ""},
      {"--BundleAdjustment.refine_rig_from_world", Kind::kBool, "--fix-images all", "1",
       "3.12's refine_extrinsics"},
      {"--BundleAdjustment.refine_sensor_from_rig", Kind::kBool, "--rig-geometry fixed", "1", "3.12's"},
      {"--random_seed", Kind::kInt, "", "", kNoEffect},
      {"--log_to_stderr", Kind::kBool, "", "", kNoEffect},
      {"--log_level", Kind::kInt, "", "", kNoEffect},
      {"--BundleAdjustment.use_gpu", Kind::kBool, "", "", kNoEffect},
      {"--BundleAdjustment.gpu_index", Kind::kText, "", "", kNoEffect},
      {"--threads", Kind::kInt, "--threads", "", "dba's own, not COLMAP's (default: every core)"},
  };
  return t;
}

void PrintColmapHelp(std::ostream& out) {
  out << "Usage: dba colmap-bundle-adjuster --input_path DIR --output_path DIR [COLMAP options]\n\n"
         "A drop-in for `colmap bundle_adjuster` (COLMAP 3.8's options and 3.12's), with\n"
         "COLMAP's defaults; each option becomes dba solve's:\n";
  for (const ColmapOption& o : Options()) {
    std::string line = o.dba;
    if (o.kind == Kind::kBool && !line.empty()) line = (*o.colmap_default == '1' ? "0: " : "1: ") + line;
    if (*o.colmap_default != '\0') line += " (COLMAP's default " + std::string(o.colmap_default) + ")";
    if (*o.note != '\0') line += (line.empty() ? "" : "; ") + std::string(o.note);
    out << "  " << o.name << kValueNames[static_cast<int>(o.kind)] << "\n      "
        << option_table_internal::Wrap(line, 74, 74, 6) << "\n";
  }
  out << "Values are read as COLMAP reads them: a boolean is 1, 0, true, false, yes, no, on\n"
         "or off in any case; an option takes the next argument as its value, or --name=value;\n"
         "an unambiguous start of a name stands for it. Any other option, an option given\n"
         "twice or a word that is no option's value is refused (exit 2).\n"
         "The gauge is COLMAP's (--gauge colmap): the first image's pose and the x of the\n"
         "second's translation (the model's file order) are kept; the final cost is COLMAP's\n"
         "optimum's.\n";
}

// The option `name` stands for: its own, or the one it starts (as boost
// guesses).
const ColmapOption& Find(const std::string& name) {
  std::vector<const ColmapOption*> starts;
  for (const ColmapOption& o : Options()) {
    if (name == o.name) return o;
    if (name.size() > 2 && name.starts_with("--") && std::string_view(o.name).starts_with(name)) {
      starts.push_back(&o);
    }
  }
  if (starts.size() == 1) return *starts[0];
  if (starts.empty()) {
    throw UsageError("'" + Clipped(name) +
                     "' is not an option of colmap bundle_adjuster that dba maps (see --help)");
  }
  std::string names;
  for (const ColmapOption* o : starts) names += (names.empty() ? "" : ", ") + std::string(o->name);
  throw UsageError(name + " is ambiguous: it starts " + names);
}

// `value` as COLMAP parses the option's kind and, for a number dba solve
// takes, in the range dba's option has; as dba solve takes it.
std::string Checked(const ColmapOption& o, const std::string& value) {
  if (o.kind == Kind::kBool) return ColmapBool(o.name, value);
  if (o.kind != Kind::kInt && o.kind != Kind::kReal) return value;
  const std::string v = o.kind == Kind::kInt ? ColmapInt(o.name, value) : ColmapReal(o.name, value);
  const auto& table = SolveOptionTable();
  const auto spec =
      std::find_if(table.begin(), table.end(), [&](const auto& s) { return s.name == o.dba; });
  if (spec == table.end()) return v;
  if (o.kind == Kind::kInt) {
    OptionInteger(o.name, v, static_cast<int64_t>(spec->min), static_cast<int64_t>(spec->max));
  } else {
    OptionNumber(o.name, v, spec->min, spec->max);
  }
  return v;
}

// The options given, by entry of Options(), each value checked; empty when
// --help was given.
std::map<const ColmapOption*, std::string> Parse(const std::vector<std::string>& args, bool* help) {
  std::map<const ColmapOption*, std::string> given;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.size() < 2 || a[0] != '-' || a == "--") {
      throw UsageError("unexpected argument '" + Clipped(a) +
                       "': colmap bundle_adjuster takes options only, --name value or --name=value "
                       "(COLMAP 3.8 ignores such a word; dba refuses it)");
    }
    const size_t eq = a.find('=');
    const ColmapOption& o = Find(a == "-h" ? "--help" : a.substr(0, eq));
    if (o.kind == Kind::kRefused) throw UsageError(std::string(o.name) + ": " + o.note);
    std::string value;
    if (eq != std::string::npos) {
      value = a.substr(eq + 1);
      if (value.empty() || o.kind == Kind::kHelp) {
        throw UsageError(o.name +
                         std::string(value.empty() ? ": no value after '='" : ": takes no value"));
      }
    } else if (o.kind != Kind::kHelp) {
      if (i + 1 == args.size()) {
        throw UsageError(o.name + std::string(": needs a value (the command line ends)"));
      }
      value = args[++i];
    }
    if (given.count(&o)) {
      throw UsageError(o.name + std::string(": given more than once (COLMAP refuses it too)"));
    }
    given[&o] = Checked(o, value);
  }
  *help = std::any_of(given.begin(), given.end(),
                      [](const auto& g) { return g.first->kind == Kind::kHelp; });
  if (*help) given.clear();
  return given;
}

const ColmapOption& Named(const char* name) {
  return *std::find_if(Options().begin(), Options().end(), [&](const ColmapOption& o) {
    return std::string_view(o.name) == name;
  });
}

// The checks COLMAP makes before its solve: the input a model directory
// (bad input, exit 1), the output a directory (made when missing here) that
// a binary model can be written into.
void CheckPaths(const std::string& input, const std::string& output) {
  std::error_code ec;
  if (!std::filesystem::is_directory(input, ec) || !DetectColmapFormat(input).has_value()) {
    throw InputError("--input_path " + (input.empty() ? "''" : input), 0,
                     std::filesystem::is_directory(input, ec)
                         ? "holds no COLMAP model (cameras, images and points3D, .bin or .txt)"
                         : "is not a directory (COLMAP's model directory)");
  }
  if (output.empty()) throw UsageError("--output_path: an empty path names no directory");
  if (std::filesystem::exists(output, ec) && !std::filesystem::is_directory(output, ec)) {
    throw UsageError("--output_path " + output + ": is not a directory");
  }
  if (DetectColmapFormat(output) == ColmapFormat::kText) {
    throw UsageError("--output_path " + output +
                     ": holds a COLMAP text model; COLMAP 3.8 would write its binary model beside "
                     "it (and read that one from then on), dba writes no model beside one in the "
                     "other format: remove the .txt files or write into another directory");
  }
}

// dba solve's arguments for the options given; `names` gets the COLMAP
// option each dba option came from.
std::vector<std::string> SolveArguments(const std::map<const ColmapOption*, std::string>& given,
                                        std::map<std::string, std::string>* names) {
  const std::string input = given.at(&Named("--input_path"));
  std::vector<std::string> solve = {input.starts_with('-') ? "./" + input : input};
  std::set<std::string> added;
  for (const ColmapOption& o : Options()) {
    const auto it = given.find(&o);
    const std::string value = it != given.end() ? it->second : o.colmap_default;
    const bool as_default = o.kind == Kind::kBool && value == o.colmap_default;
    if (*o.dba == '\0' || value.empty() || as_default) continue;
    std::istringstream words(o.dba);
    const std::string flag = *std::istream_iterator<std::string>(words);
    if (it != given.end()) (*names)[flag] = o.name;
    if (o.kind != Kind::kBool) {
      solve.insert(solve.end(), {flag, value});
    } else if (added.insert(o.dba).second) {
      solve.push_back(flag);
      for (std::string w; words >> w;) solve.push_back(w);
    }
  }
  solve.insert(solve.end(), {"--colmap-format", "binary"});
  solve.insert(solve.end(), {"--gauge", "colmap"});  // what COLMAP holds (camera/gauge_hold.h)
  return solve;
}

// `colmap bundle_adjuster`'s arguments as `dba solve`'s (none with --help);
// `names` gets the COLMAP option each dba option came from. Throws
// UsageError, or InputError for an input that is not a model directory.
std::vector<std::string> SolveArgumentsOfColmap(const std::vector<std::string>& args, bool* help,
                                                std::map<std::string, std::string>* names) {
  const std::map<const ColmapOption*, std::string> given = Parse(args, help);
  if (*help) return {};
  for (const char* required : {"--input_path", "--output_path"}) {
    if (!given.count(&Named(required))) throw UsageError(std::string(required) + " is required");
  }
  CheckPaths(given.at(&Named("--input_path")), given.at(&Named("--output_path")));
  return SolveArguments(given, names);
}

}  // namespace

int ColmapBundleAdjusterMain(const std::vector<std::string>& args) {
  std::vector<std::string> solve;
  std::map<std::string, std::string> names;
  bool help = args.empty();
  try {
    if (!help) solve = SolveArgumentsOfColmap(args, &help, &names);
  } catch (const std::exception& e) {
    std::cerr << "dba colmap-bundle-adjuster: " << e.what() << "\n";
    return dynamic_cast<const InputError*>(&e) != nullptr ? 1 : 2;
  }
  if (help) {
    PrintColmapHelp(std::cout);
    return args.empty() ? 2 : 0;
  }
  std::cout << "dba colmap-bundle-adjuster: dba solve";
  for (const std::string& a : solve) std::cout << " " << a;
  std::cout << "\n";
  // dba solve's messages name the COLMAP option a dba option came from.
  return SolveMain(solve, [&](const std::string& message) {
    for (const auto& [dba, colmap] : names) {
      if (message.starts_with(dba + " ") || message.starts_with(dba + ":")) {
        return colmap + message.substr(dba.size());
      }
    }
    return message;
  });
}

}  // namespace dba
