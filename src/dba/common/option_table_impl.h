// The templates of common/option_table.h: the parser, the help and the
// Markdown table over any options struct.
#pragma once

#include <algorithm>
#include <ostream>
#include <set>
#include <sstream>
#include <stdexcept>

namespace dba {
namespace option_table_internal {

// `text` wrapped to `width` columns, each line after the first indented by
// `indent` spaces ("\n" starts a new line).
std::string Wrap(const std::string& text, size_t first_width, size_t width, size_t indent);

}  // namespace option_table_internal

template <typename Options>
void ParseOptions(const std::vector<OptionSpec<Options>>& table,
                  const std::vector<std::string>& args, Options* options,
                  const std::function<void(const std::string&)>& positional, bool* help,
                  const char* command) {
  *help = false;
  std::set<std::string> given;
  bool options_end = false;  // after "--": positional only
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (!options_end && a == "--") {
      options_end = true;
      continue;
    }
    if (!options_end && (a == "-h" || a == "--help")) {
      *help = true;
      return;
    }
    if (options_end || a.size() < 2 || a[0] != '-') {
      positional(a);
      continue;
    }
    const auto spec = std::find_if(table.begin(), table.end(), [&](const OptionSpec<Options>& s) {
      return s.name == a || (!s.alias.empty() && s.alias == a);
    });
    if (spec == table.end()) {
      throw std::invalid_argument("unknown option '" + a + "' (see dba " + command + " --help)");
    }
    if (!given.insert(spec->name).second && !spec->repeatable) {
      throw std::invalid_argument(a + ": given twice (it is not repeatable)");
    }
    std::string value;
    if (spec->kind != OptionKind::kFlag) {
      if (i + 1 >= args.size()) throw std::invalid_argument(a + ": missing value");
      if (args[i + 1].empty()) throw std::invalid_argument(a + ": an empty value");
      value = args[++i];
    }
    spec->set(*options, value);
  }
  for (const OptionSpec<Options>& s : table) {
    if (s.needs_met && given.contains(s.name) && !s.needs_met(*options)) {
      throw std::invalid_argument(s.name + " needs " + s.needs);
    }
  }
}

template <typename Options>
void PrintOptions(const std::vector<OptionSpec<Options>>& table, const Options& defaults,
                  std::ostream& out) {
  constexpr size_t kColumn = 29;
  for (const OptionSpec<Options>& s : table) {
    std::string head = "  " + (s.alias.empty() ? s.name : s.alias + ", " + s.name);
    if (!s.value.empty()) head += " " + s.value;
    std::string help = s.help;
    const std::string d = s.default_text ? s.default_text(defaults) : std::string();
    const std::string needs = s.needs.empty() ? "" : "needs " + s.needs;
    if (!needs.empty() || !d.empty()) {
      help += " (" + needs + (needs.empty() || d.empty() ? "" : "; ") +
              (d.empty() ? "" : "default " + d) + ")";
    }
    if (head.size() + 1 > kColumn) {
      out << head << "\n" << std::string(kColumn, ' ');
    } else {
      out << head << std::string(kColumn - head.size(), ' ');
    }
    out << option_table_internal::Wrap(help, 80 - kColumn, 80 - kColumn, kColumn) << "\n";
  }
}

template <typename Options>
std::string OptionsMarkdown(const std::vector<OptionSpec<Options>>& table,
                            const Options& defaults) {
  std::ostringstream md;
  md << "| option | value | default | Python | what it does |\n"
        "|---|---|---|---|---|\n";
  for (const OptionSpec<Options>& s : table) {
    const std::string d = s.default_text ? s.default_text(defaults) : std::string();
    std::string value = s.value;
    std::replace(value.begin(), value.end(), '|', '/');
    std::string python = "`" + PythonKeyword(s.name) + "`";
    if (!(s.modes & kModePythonArrays)) python += " (not solve_arrays)";
    if (!(s.modes & kModePythonFile)) python = "–";
    std::string help = s.help + (s.needs.empty() ? "" : " (needs " + s.needs + ")");
    std::replace(help.begin(), help.end(), '\n', ' ');
    std::replace(help.begin(), help.end(), '|', '/');
    md << "| `" << (s.alias.empty() ? "" : s.alias + "`, `") << s.name << "` | "
       << (value.empty() ? "" : "`" + value + "`") << " | " << d << " | " << python << " | "
       << help << " |\n";
  }
  return md.str();
}

}  // namespace dba
