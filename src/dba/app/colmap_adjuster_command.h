// `dba colmap-bundle-adjuster`: a drop-in for `colmap bundle_adjuster`. It
// takes COLMAP's command line (3.8's option names and 3.12's) as COLMAP 3.8
// reads it (boost::program_options: each value of the type COLMAP parses it
// as, booleans spelled any way boost takes, a name's unambiguous start, an
// option once), with COLMAP's defaults (100 iterations, tolerances 0,
// principal point fixed), checks the paths as COLMAP does, maps each option
// onto `dba solve`'s and runs that solve (one process, or every rank under
// mpirun), writing the model in COLMAP's binary format as COLMAP 3.8 does
// whatever the input's. An option dba cannot honour, a repeated one and a
// stray word are refused by name (exit 2); every message names COLMAP's
// option. The gauge is COLMAP's (`--gauge colmap`, camera/gauge_hold.h):
// the first image's pose and the x of the second's translation, in the
// model's file order, as COLMAP 3.8 holds them; the optimum, its cost and
// its frame are COLMAP's.
#pragma once

#include <string>
#include <vector>

namespace dba {

// `dba colmap-bundle-adjuster ARGS...`: the exit status (0 success, 1
// failure or bad input, 2 bad arguments).
int ColmapBundleAdjusterMain(const std::vector<std::string>& args);

}  // namespace dba
