// Reads a problem file of any supported kind: the dba binary format (by its
// magic) or BAL text, plain or bzip2. Throws InputError.
#pragma once

#include <string>

#include "dba/io/bal_reader.h"
#include "dba/io/binary_problem.h"

namespace dba {

// A directory is refused with a message that says what it holds.
Problem ReadProblem(const std::string& path);

// Writes BAL text (.txt, .bz2 compressed) or, for a .dba path, the binary
// format.
void WriteProblem(const Problem& problem, const std::string& path);

}  // namespace dba
