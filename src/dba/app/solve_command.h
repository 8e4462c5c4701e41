// `dba solve`: read a problem, run LM, print the summary, write the outputs.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "dba/geo/georeference.h"
#include "dba/app/solve_input.h"
#include "dba/app/solve_report.h"
#include "dba/cluster/communicator.h"
#include "dba/cluster/distributed_solve.h"
#include "dba/lm/levenberg_marquardt.h"

namespace dba {

struct SolveCommandOptions {
  std::string input;
  std::string output;       // empty: no output file
  std::string report_path;  // empty: no JSON report
  std::string truth_path;   // empty: no ground-truth comparison
  bool truth_absolute = false;  // compare with no similarity alignment
  std::string ply_path;     // empty: no point cloud
  // io/checkpoint.h: written after accepted iterations (at most every
  // checkpoint_every_s seconds; 0: after each), and a solve resumed from one.
  std::string checkpoint_path;
  double checkpoint_every_s = 0.0;
  std::string resume_path;
  std::optional<ColmapFormat> colmap_format;  // COLMAP output; default: the input's
  UnknownsOptions unknowns; // what is held fixed, shared intrinsics
  bool quiet = false;       // no per-iteration log
  bool progress = true;     // progress of long phases on a terminal (not with quiet)
  double reject_outliers_px = 0.0;  // > 0: rounds of outlier rejection (lm/outlier_rejection.h)
  // With rejection: points whose rays meet at less than this also go (0: off).
  double min_triangulation_angle_deg = RejectionCriteria().min_triangulation_angle_deg;
  // The solves after a rejection round keep the robust loss (false: the
  // squared loss, the efficient estimator once the outliers are gone).
  bool reject_keep_loss = false;
  GeoreferenceOptions geo;  // --camera-priors, --gcps and their CRSs
  // One process: refuse to start when the memory estimate exceeds what the
  // machine (or the cgroup) has available; false: --no-memory-check.
  bool memory_check = true;
  LmOptions lm;             // num_threads 0: the node's cores / its ranks
  DistributedOptions distributed;
};

// Parses the arguments after `solve`. Throws std::invalid_argument with a
// message naming the bad argument. Sets *help when --help was given.
SolveCommandOptions ParseSolveArguments(const std::vector<std::string>& args,
                                        bool* help);
void PrintSolveHelp(std::ostream& out);

// What a solve leaves besides what it prints and writes (main rank): the
// summary and the adjusted problem (after --reject-outliers, the observations
// and points kept). For library callers such as the Python module.
struct SolveOutcome {
  SolveReport report;
  Problem problem;
};

// Runs the command on every rank of `comm` (collective); only the main rank
// prints and writes. Returns the process exit status; throws on failure.
// `outcome` (optional) receives the summary and the adjusted problem.
int RunSolveCommand(const SolveCommandOptions& options, Communicator* comm,
                    std::ostream& out, SolveOutcome* outcome = nullptr);

// Refuses (std::runtime_error naming `input` and the first observations) a
// problem whose initial cost is not finite.
void RefuseNonFiniteResiduals(const std::string& input, const Problem& problem);

// `dba solve ARGS...`: parses, runs, reports errors; returns the exit status
// (0 success, 1 failure, 2 bad arguments).
int SolveMain(const std::vector<std::string>& args);

}  // namespace dba
