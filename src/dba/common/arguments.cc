// Command-line values beyond one number; see arguments.h.
#include "dba/common/arguments.h"

#include "dba/common/option_table.h"

namespace dba {

std::pair<double, double> ParseSigmaPair(const std::string& flag, const std::string& value) {
  const size_t comma = value.find(',');
  const double xy = OptionNumber(flag, value.substr(0, comma), 1e-6, 1e6);
  const double z =
      comma == std::string::npos ? xy : OptionNumber(flag, value.substr(comma + 1), 1e-6, 1e6);
  return {xy, z};
}

std::array<double, 3> ParseTriple(const std::string& flag, const std::string& value, double limit) {
  std::array<double, 3> v{};
  size_t start = 0;
  for (int k = 0; k < 3; ++k) {
    const size_t comma = value.find(',', start);
    if ((k < 2) == (comma == std::string::npos)) {
      throw std::invalid_argument(flag + ": '" + value + "' is not X,Y,Z (three numbers)");
    }
    v[k] = OptionNumber(flag, value.substr(start, comma - start), -limit, limit);
    start = comma + 1;
  }
  return v;
}

}  // namespace dba
