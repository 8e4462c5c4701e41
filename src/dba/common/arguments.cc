// Command-line value parsing; see arguments.h.
#include "dba/common/arguments.h"

#include <charconv>
#include <cmath>
#include <stdexcept>

namespace dba {

double ParseNumberArgument(const std::string& flag, const std::string& value, double min) {
  double v = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
  if (ec != std::errc() || end != value.data() + value.size() || !std::isfinite(v) || v < min) {
    throw std::invalid_argument(flag + ": expected a number >= " + std::to_string(min) +
                                ", got '" + value + "'");
  }
  return v;
}

int64_t ParseIntegerArgument(const std::string& flag, const std::string& value, int64_t min,
                             int64_t max) {
  int64_t v = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
  if (ec != std::errc() || end != value.data() + value.size() || v < min || v > max) {
    throw std::invalid_argument(flag + ": expected an integer in [" + std::to_string(min) +
                                ", " + std::to_string(max) + "], got '" + value + "'");
  }
  return v;
}

std::pair<double, double> ParseSigmaPair(const std::string& flag, const std::string& value) {
  const size_t comma = value.find(',');
  const double xy = ParseNumberArgument(flag, value.substr(0, comma));
  const double z = comma == std::string::npos ? xy : ParseNumberArgument(flag, value.substr(comma + 1));
  if (!(xy > 0.0 && z > 0.0)) throw std::invalid_argument(flag + ": expected XY,Z both > 0 (metres)");
  return {xy, z};
}

}  // namespace dba
