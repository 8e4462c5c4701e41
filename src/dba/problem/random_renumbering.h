// A problem with its points and cameras renumbered by a seeded random
// permutation: the same problem in an order nobody chose (`dba convert
// --shuffle`), to show that the input's order changes no result beyond
// rounding and to time what a scattered input costs.
#pragma once

#include <cstdint>

#include "dba/problem/problem.h"

namespace dba {

// Renumbers `problem`'s points and cameras (images; intrinsic groups keep
// their numbers) by permutations drawn from `seed` (std::mt19937_64 and a
// Fisher–Yates shuffle of our own: the same seed gives the same problem on
// every platform); each point's observations come sorted by their new
// camera numbers. Priors and fixed flags follow their points and cameras.
void RenumberAtRandom(uint64_t seed, Problem* problem);

}  // namespace dba
