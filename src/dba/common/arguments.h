// Command-line values beyond one number (common/option_table.h parses
// those): every error names the flag and the value it did not accept.
// Thread safety: pure functions.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

#include "dba/common/error.h"

namespace dba {

// Threads per rank above this are refused (OpenMP's runtime fails far below
// its own limits).
inline constexpr int64_t kMaxThreads = 1024;

// "XY,Z" (or "S" for both): two σ in metres, both in (0, 1e6] (--prior-sigma,
// --gnss-sigma); throws std::invalid_argument naming the flag.
std::pair<double, double> ParseSigmaPair(const std::string& flag, const std::string& value);

// "X,Y,Z": three numbers, each in [-limit, limit] (--lever-arm); throws
// std::invalid_argument naming the flag.
std::array<double, 3> ParseTriple(const std::string& flag, const std::string& value, double limit);

}  // namespace dba
