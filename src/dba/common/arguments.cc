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

}  // namespace dba
