// The values of COLMAP 3.8's command line as it reads them
// (boost::program_options: boost::lexical_cast for numbers, boost's own
// validator for booleans), for `dba colmap-bundle-adjuster`. Each returns
// the value as dba solve takes it, or throws UsageError naming `flag` and
// the value.
//
// Thread safety: pure functions.
#pragma once

#include <string>

namespace dba {

// An int: an optional sign and decimal digits, in 32 bits; as decimal digits
// with a '-' only.
std::string ColmapInt(const std::string& flag, const std::string& value);

// A double: a decimal number with an optional sign and exponent, inf or nan;
// an overflow is refused, an underflow is 0; as the shortest text of the
// same double.
std::string ColmapReal(const std::string& flag, const std::string& value);

// A bool: 1, true, yes, on (or empty), 0, false, no, off, in any case; as 1
// or 0.
std::string ColmapBool(const std::string& flag, const std::string& value);

}  // namespace dba
