// Command-line value parsing shared by the subcommands: every error names the
// flag and the value it did not accept. Thread safety: pure functions.
#pragma once

#include <cstdint>
#include <string>

namespace dba {

// A finite number >= min; throws std::invalid_argument otherwise.
double ParseNumberArgument(const std::string& flag, const std::string& value,
                           double min = 0.0);
// An integer in [min, max]; throws std::invalid_argument otherwise.
int64_t ParseIntegerArgument(const std::string& flag, const std::string& value, int64_t min,
                             int64_t max = int64_t{1} << 40);

}  // namespace dba
