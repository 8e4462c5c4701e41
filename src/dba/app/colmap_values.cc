// COLMAP 3.8's command-line values; see colmap_values.h.
#include "dba/app/colmap_values.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "dba/common/error.h"

namespace dba {
namespace {

// `v` without the '+' boost::lexical_cast takes before a number (from_chars
// does not); "" (no number) for a sign after it.
std::string_view WithoutPlus(const std::string& v) {
  if (!v.starts_with('+')) return v;
  const std::string_view s = std::string_view(v).substr(1);
  return s.starts_with('+') || s.starts_with('-') ? std::string_view() : s;
}

}  // namespace

// boost::lexical_cast<int>.
std::string ColmapInt(const std::string& flag, const std::string& v) {
  const std::string_view s = WithoutPlus(v);
  int32_t n = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), n);
  if (ec != std::errc() || end != s.data() + s.size()) {
    throw UsageError(flag + ": '" + Clipped(v) +
                     "' is not an integer (COLMAP's int: -2147483648 to 2147483647)");
  }
  return std::to_string(n);
}

// boost::lexical_cast<double>.
std::string ColmapReal(const std::string& flag, const std::string& v) {
  const std::string_view s = WithoutPlus(v);
  double d = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), d);
  const bool range = ec == std::errc::result_out_of_range;
  if (range) d = std::strtod(std::string(s).c_str(), nullptr);  // +-inf or about 0
  if ((ec != std::errc() && !range) || (range && std::isinf(d)) || end != s.data() + s.size()) {
    throw UsageError(flag + ": '" + Clipped(v) + "' is not a number");
  }
  char text[32];
  return std::string(text, std::to_chars(text, text + sizeof text, d).ptr);
}

// boost::program_options' validator of bool.
std::string ColmapBool(const std::string& flag, const std::string& v) {
  std::string s = v;
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  if (s.empty() || s == "1" || s == "true" || s == "yes" || s == "on") return "1";
  if (s == "0" || s == "false" || s == "no" || s == "off") return "0";
  throw UsageError(flag + ": '" + Clipped(v) +
                   "' is not a boolean (COLMAP's: 1, 0, true, false, yes, no, on, off, in any case)");
}

}  // namespace dba
