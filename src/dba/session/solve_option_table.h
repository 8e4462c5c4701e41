// `dba solve`'s options, each declared once (common/option_table.h): the
// parser (ParseSolveArguments), `dba solve --help`, the Python keywords of
// dba.solve and dba.solve_arrays, and README.md's option table are made
// from this table.
//
// Thread safety: the table is built once and immutable.
#pragma once

#include <vector>

#include "dba/common/option_table.h"
#include "dba/session/solve_options.h"

namespace dba {

const std::vector<OptionSpec<SolveOptions>>& SolveOptionTable();

}  // namespace dba
