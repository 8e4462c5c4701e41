// Options declared once: each option of a command is one entry of a table
// (its name, the kind of value it takes and that value's range, its help,
// its default, what it needs, where it applies and how it lands in the
// options struct),
// and the parser, `--help`, the Python keywords and the README's table are
// all made from the table (session/solve_option_table.h for `dba solve`).
//
// Thread safety: a table is immutable once built; parsing is a pure
// function of the arguments.
#pragma once

#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace dba {

// The kind of value an option takes: what the parser accepts, and what a
// Python keyword must be (a bool, an int, a float, a str or os.PathLike, a
// str among the choices, a sequence of ints or strs).
enum class OptionKind {
  kFlag,     // no value (Python: a bool)
  kInteger,  // an integer in [min, max]
  kNumber,   // a finite number in [min, max] (exclusive where said)
  kText,     // any non-empty text (a CRS, a fixing)
  kPath,     // a file or directory
  kChoice,   // one of `choices`
  kList,     // comma-separated values (Python: a sequence)
};
const char* OptionKindName(OptionKind kind);

// Where an option applies: a bit per way a solve is started.
enum OptionMode : unsigned {
  kModeCommandLine = 1,  // dba solve, one process or N ranks
  kModePythonFile = 2,   // dba.solve(path, ...)
  kModePythonArrays = 4, // dba.solve_arrays(...)
  kModeAll = 7,
};

template <typename Options>
struct OptionSpec {
  std::string name;   // "--max-iterations"
  std::string alias;  // "-t", or ""
  OptionKind kind = OptionKind::kFlag;
  std::string value;  // the value's name in the help: "N", "FILE", "auto|dense"
  std::string help;   // one paragraph; wrapped when printed
  // Parses `value` (empty for a flag) into the options; throws
  // std::invalid_argument naming the option and what it did not accept.
  std::function<void(Options&, const std::string&)> set;
  // The default as the help prints it ("" for none).
  std::function<std::string(const Options&)> default_text;
  std::vector<std::string> choices;  // kChoice
  double min = 0, max = 0;           // kInteger, kNumber: the range
  bool repeatable = false;           // may be given more than once
  unsigned modes = kModeAll;
  std::string not_here;  // why the modes left out do not take it
  // What the option means nothing without, as the help says it
  // ("--camera-priors or --gcps"), and whether parsed options have it
  // (defaults included); empty: it stands alone. Given without it, it is
  // refused: "--prior-crs needs --camera-priors or --gcps".
  std::string needs;
  std::function<bool(const Options&)> needs_met;
};

// The Python keyword of an option: its long name without the dashes, '-'
// made '_' ("--max-iterations" -> "max_iterations", "--output" -> "output").
std::string PythonKeyword(const std::string& name);

// Parses `args` into `options` by the table: every option by name or alias
// (a flag alone, others followed by a non-empty value), everything else
// handed to `positional`, and everything after "--" too (a path may start
// with '-'). Throws std::invalid_argument for an unknown option, a missing
// or empty value, a value out of its range, an option given twice that is
// not repeatable, and an option given without what it needs. Sets *help on
// -h/--help and stops.
template <typename Options>
void ParseOptions(const std::vector<OptionSpec<Options>>& table,
                  const std::vector<std::string>& args, Options* options,
                  const std::function<void(const std::string&)>& positional, bool* help,
                  const char* command);

// The options as `--help` lists them: name, value, help wrapped to 80
// columns, "(needs X; default Y)" from `needs` and `defaults`.
template <typename Options>
void PrintOptions(const std::vector<OptionSpec<Options>>& table, const Options& defaults,
                  std::ostream& out);

// The table as Markdown (README.md's): option, value, default, Python
// keyword, help (with what it needs).
template <typename Options>
std::string OptionsMarkdown(const std::vector<OptionSpec<Options>>& table,
                            const Options& defaults);

// Value parsers for the table's setters; each throws std::invalid_argument
// naming `flag` and the value.
int64_t OptionInteger(const std::string& flag, const std::string& value, int64_t min, int64_t max);
// A finite number in [min, max], or (min, max] when `above_min`.
double OptionNumber(const std::string& flag, const std::string& value, double min, double max,
                    bool above_min = false);
// The index of `value` among `choices`.
size_t OptionChoice(const std::string& flag, const std::string& value,
                    const std::vector<std::string>& choices);
// "%g" of a number, for defaults.
std::string OptionNumberText(double value);

// What `spec` needs (OptionSpec::needs): `text` for the help and the
// refusal, `met` judging the parsed options.
template <typename Options, typename Met>
void SetNeeds(OptionSpec<Options>* spec, std::string text, Met met) {
  spec->needs = std::move(text);
  spec->needs_met = met;
}

// Entries of a table, by kind; `field` is a (generic) lambda giving the
// options' field the value lands in, const or not:
//   [](auto& o) -> auto& { return o.lm.max_iterations; }
template <typename Options>
OptionSpec<Options> OptionEntry(std::string name, OptionKind kind, std::string value,
                                std::string help) {
  OptionSpec<Options> s;
  s.name = std::move(name);
  s.kind = kind;
  s.value = std::move(value);
  s.help = std::move(help);
  return s;
}

template <typename Options, typename F>
OptionSpec<Options> PathOption(std::string name, std::string value, std::string help, F field) {
  OptionSpec<Options> s = OptionEntry<Options>(std::move(name), OptionKind::kPath,
                                               std::move(value), std::move(help));
  s.set = [field](Options& o, const std::string& v) { field(o) = v; };
  return s;
}

template <typename Options, typename F>
OptionSpec<Options> TextOption(std::string name, std::string value, std::string help, F field) {
  OptionSpec<Options> s = OptionEntry<Options>(std::move(name), OptionKind::kText,
                                               std::move(value), std::move(help));
  s.set = [field](Options& o, const std::string& v) { field(o) = v; };
  return s;
}

template <typename Options, typename F>
OptionSpec<Options> FlagOption(std::string name, std::string help, F field) {
  OptionSpec<Options> s =
      OptionEntry<Options>(std::move(name), OptionKind::kFlag, "", std::move(help));
  s.set = [field](Options& o, const std::string&) { field(o) = true; };
  return s;
}

// A finite number in [min, max] ((min, max] with `above_min`).
template <typename Options, typename F>
OptionSpec<Options> NumberOption(std::string name, std::string value, std::string help, F field,
                                 double min, double max, bool above_min = false) {
  OptionSpec<Options> s =
      OptionEntry<Options>(name, OptionKind::kNumber, std::move(value), std::move(help));
  s.min = min;
  s.max = max;
  s.set = [=](Options& o, const std::string& v) {
    field(o) = OptionNumber(name, v, min, max, above_min);
  };
  s.default_text = [field](const Options& o) { return OptionNumberText(field(o)); };
  return s;
}

template <typename Options, typename F>
OptionSpec<Options> IntegerOption(std::string name, std::string value, std::string help, F field,
                                  int64_t min, int64_t max) {
  OptionSpec<Options> s =
      OptionEntry<Options>(name, OptionKind::kInteger, std::move(value), std::move(help));
  s.min = static_cast<double>(min);
  s.max = static_cast<double>(max);
  s.set = [=](Options& o, const std::string& v) {
    using T = std::decay_t<decltype(field(o))>;
    field(o) = static_cast<T>(OptionInteger(name, v, min, max));
  };
  s.default_text = [field](const Options& o) { return std::to_string(field(o)); };
  return s;
}

// One of `choices`: `apply` takes its index, `current` shows the default.
template <typename Options, typename Apply, typename Current>
OptionSpec<Options> ChoiceOption(std::string name, std::vector<std::string> choices,
                                 std::string help, Apply apply, Current current) {
  std::string value;
  for (const std::string& c : choices) value += (value.empty() ? "" : "|") + c;
  OptionSpec<Options> s = OptionEntry<Options>(name, OptionKind::kChoice, value, std::move(help));
  s.choices = choices;
  s.set = [=](Options& o, const std::string& v) { apply(o, OptionChoice(name, v, choices)); };
  s.default_text = current;
  return s;
}

}  // namespace dba

#include "dba/common/option_table_impl.h"
