// `dba colmap-bundle-adjuster`: a drop-in for `colmap bundle_adjuster`. It
// takes COLMAP's command line (3.8's option names and 3.12's), with COLMAP's
// defaults (100 iterations, tolerances 0, principal point fixed), maps each
// option onto `dba solve`'s and runs that solve (one process, or every rank
// under mpirun); an option dba cannot honour is refused by name (exit 2).
// The gauge is COLMAP's (`--gauge colmap`, camera/gauge_hold.h): the first
// image's pose and the x of the second's translation, in the model's file
// order, as COLMAP 3.8 holds them; the optimum, its cost and its frame are
// COLMAP's.
#pragma once

#include <string>
#include <vector>

namespace dba {

// `colmap bundle_adjuster`'s arguments (--name value or --name=value) as
// `dba solve`'s. Throws UsageError naming an unknown or refused option, a
// missing --input_path / --output_path, or a bad value.
std::vector<std::string> SolveArgumentsOfColmap(const std::vector<std::string>& args);

// `dba colmap-bundle-adjuster ARGS...`: the exit status (0 success, 1
// failure, 2 bad arguments).
int ColmapBundleAdjusterMain(const std::vector<std::string>& args);

}  // namespace dba
