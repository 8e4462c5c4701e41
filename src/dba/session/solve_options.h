// The options of a solve, whichever way it is started (the command line, N
// ranks, Python), their parser from command-line arguments and their help.
//
// Thread safety: pure functions.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "dba/camera/gauge_hold.h"
#include "dba/cluster/distributed_solve.h"
#include "dba/geo/georeference.h"
#include "dba/lm/levenberg_marquardt.h"
#include "dba/lm/outlier_rejection.h"
#include "dba/lm/rejection_guard.h"
#include "dba/session/solve_input.h"

namespace dba {

struct SolveOptions {
  std::string input;
  std::string output;       // empty: no output file
  std::string report_path;  // empty: no JSON report
  std::string truth_path;   // empty: no ground-truth comparison
  bool truth_absolute = false;  // compare with no similarity alignment
  std::string ply_path;     // empty: no point cloud
  bool ply_sigma = false;   // --ply-colour sigma: the points coloured by their sigma
  // io/checkpoint.h: written after accepted iterations (at most every
  // checkpoint_every_s seconds; 0: after each), and a solve resumed from one.
  std::string checkpoint_path;
  double checkpoint_every_s = 0.0;
  std::string resume_path;
  std::optional<ColmapFormat> colmap_format;  // COLMAP output; default: the input's
  // --colmap-version 3.8: a COLMAP output must load in COLMAP 3.8 (its
  // camera models only); false: a lens model it lacks is written with a
  // warning.
  bool colmap_38 = false;
  UnknownsOptions unknowns; // what is held fixed, shared intrinsics
  bool quiet = false;       // no per-iteration log
  bool progress = true;     // progress of long phases on a terminal (not with quiet)
  double reject_outliers_px = 0.0;  // > 0: rounds of outlier rejection (lm/outlier_rejection.h)
  // With rejection: points whose rays meet at less than this also go (0: off).
  double min_triangulation_angle_deg = RejectionCriteria().min_triangulation_angle_deg;
  // The solves after a rejection round keep the robust loss (false: the
  // squared loss, the efficient estimator once the outliers are gone).
  bool reject_keep_loss = false;
  // A rejection round that would drop more than this share of the
  // observations, or leave a pose without the observations that determine
  // it, stops the run (lm/rejection_guard.h); 1: no guard.
  double reject_max_share = RejectionGuard().max_share;
  // Whether --loss and --loss-scale were given: with --reject-outliers and
  // no --loss, the first solve takes RejectionStartLoss.
  bool loss_given = false;
  bool loss_scale_given = false;
  GeoreferenceOptions geo;  // --camera-priors, --gcps and their CRSs
  // One process: refuse to start when the memory estimate exceeds what the
  // machine (or the cgroup) has available; false: --no-memory-check.
  bool memory_check = true;
  // What is held of the 7 degrees of freedom nothing else holds
  // (camera/gauge_hold.h): --gauge hold, free (the optimum where LM ends)
  // or colmap (colmap bundle_adjuster's).
  GaugeRule gauge = GaugeRule::kHold;
  // --covariance FILE: every image's pose covariance at the optimum
  // (precision/camera_covariance.h), scaled by the variance factor σ̂₀²
  // unless --covariance-scale unit (a pixel σ of 1).
  std::string covariance_path;
  std::string point_covariance_path;  // --point-covariance FILE: each point's 3×3
  bool covariance_unit = false;
  LmOptions lm;             // num_threads 0: the node's cores / its ranks
  DistributedOptions distributed;
};

// Parses the arguments after `solve`. Throws std::invalid_argument with a
// message naming the bad argument. Sets *help when --help was given. With
// --reject-outliers and no --loss, lm.loss is the first solve's
// (RejectionStartLoss).
SolveOptions ParseSolveArguments(const std::vector<std::string>& args,
                                        bool* help);
void PrintSolveHelp(std::ostream& out);

// The threads a solve runs with by default: this node's cores.
int DefaultThreads();

}  // namespace dba
