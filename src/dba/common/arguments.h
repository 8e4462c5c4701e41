// Command-line value parsing shared by the subcommands: every error names the
// flag and the value it did not accept. Thread safety: pure functions.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include "dba/common/error.h"

namespace dba {


// Threads per rank above this are refused (OpenMP's runtime fails far below
// its own limits).
inline constexpr int64_t kMaxThreads = 1024;

// A finite number >= min; throws std::invalid_argument otherwise.
double ParseNumberArgument(const std::string& flag, const std::string& value,
                           double min = 0.0);

// "XY,Z" (or "S" for both): two σ in metres, both > 0 (--prior-sigma,
// --gnss-sigma); throws std::invalid_argument naming the flag.
std::pair<double, double> ParseSigmaPair(const std::string& flag, const std::string& value);
// An integer in [min, max]; throws std::invalid_argument otherwise.
int64_t ParseIntegerArgument(const std::string& flag, const std::string& value, int64_t min,
                             int64_t max = int64_t{1} << 40);

}  // namespace dba
