// Options declared once; see option_table.h.
#include "dba/common/option_table.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace dba {

const char* OptionKindName(OptionKind kind) {
  switch (kind) {
    case OptionKind::kFlag: return "flag";
    case OptionKind::kInteger: return "integer";
    case OptionKind::kNumber: return "number";
    case OptionKind::kText: return "text";
    case OptionKind::kPath: return "path";
    case OptionKind::kChoice: return "choice";
    case OptionKind::kList: return "list";
  }
  return "unknown";
}

std::string PythonKeyword(const std::string& name) {
  std::string k = name.substr(name.find_first_not_of('-'));
  for (char& c : k) {
    if (c == '-') c = '_';
  }
  return k;
}

int64_t OptionInteger(const std::string& flag, const std::string& value, int64_t min, int64_t max) {
  int64_t v = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
  if (ec != std::errc() || end != value.data() + value.size() || v < min || v > max) {
    throw std::invalid_argument(flag + ": expected an integer in [" + std::to_string(min) + ", " +
                                std::to_string(max) + "], got '" + value + "'");
  }
  return v;
}

double OptionNumber(const std::string& flag, const std::string& value, double min, double max,
                    bool above_min) {
  double v = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
  const bool ok = ec == std::errc() && end == value.data() + value.size() && std::isfinite(v) &&
                  (above_min ? v > min : v >= min) && v <= max;
  if (!ok) {
    throw std::invalid_argument(flag + ": expected a number in " + (above_min ? "(" : "[") +
                                OptionNumberText(min) + ", " + OptionNumberText(max) +
                                "], got '" + value + "'");
  }
  return v;
}

size_t OptionChoice(const std::string& flag, const std::string& value,
                    const std::vector<std::string>& choices) {
  for (size_t i = 0; i < choices.size(); ++i) {
    if (choices[i] == value) return i;
  }
  std::string list;
  for (size_t i = 0; i < choices.size(); ++i) {
    list += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i];
  }
  throw std::invalid_argument(flag + ": expected " + list + ", got '" + value + "'");
}

std::string OptionNumberText(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", value);
  return buf;
}

namespace option_table_internal {

std::string Wrap(const std::string& text, size_t first_width, size_t width, size_t indent) {
  std::string out, line;
  size_t limit = first_width;
  const auto flush = [&] {
    out += line;
    line.clear();
    limit = width;
  };
  std::istringstream paragraphs(text);
  std::string paragraph;
  bool first_paragraph = true;
  while (std::getline(paragraphs, paragraph, '\n')) {
    if (!first_paragraph) {
      flush();
      out += "\n" + std::string(indent, ' ');
    }
    first_paragraph = false;
    std::istringstream words(paragraph);
    std::string word;
    while (words >> word) {
      if (!line.empty() && line.size() + 1 + word.size() > limit) {
        flush();
        out += "\n" + std::string(indent, ' ');
      }
      line += (line.empty() ? "" : " ") + word;
    }
  }
  flush();
  return out;
}

}  // namespace option_table_internal
}  // namespace dba
