// The report of a solve: what the session measured (SolveReport), and its
// summary, computed once and rendered as text, JSON and Python's Summary.
#pragma once

#include "dba/geo/georeference.h"

#include <array>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dba/cluster/distributed_solve.h"
#include "dba/lm/memory_estimate.h"
#include "dba/lm/outlier_rejection.h"
#include "dba/precision/camera_covariance.h"
#include "dba/problem/parameter_blocks.h"
#include "dba/problem/problem.h"
#include "dba/synthetic/ground_truth.h"

namespace dba {

struct SolveReport {
  std::string input;
  int64_t num_cameras = 0;  // images (the report's num_images; num_cameras is deprecated)
  int64_t num_intrinsic_groups = 0;  // photogrammetric model; 0 for BAL
  // A COLMAP input: the model's cameras as COLMAP counts them, and those in
  // use by the images adjusted (0 for other inputs).
  int64_t num_colmap_cameras = 0, num_colmap_cameras_used = 0;
  int64_t num_colmap_sensors_not_modelled = 0;  // rig sensors that are not cameras
  int64_t num_points = 0;
  int64_t num_observations = 0;
  // At the start: observations whose point is behind its camera (-1: not
  // counted, the ranks held the observations).
  int64_t observations_behind_cameras = -1;
  int threads = 1;
  // The options that shape the linear solve and the run, as given.
  LinearSolverOptions linear_solver;
  bool memory_check = true;
  // --checkpoint: where, and how many this run wrote.
  std::string checkpoint_path;
  int64_t checkpoints_written = 0;
  RobustLoss loss;
  // The loss of the final cost: `loss`, or the squared loss when outlier
  // rejection solved again without it.
  RobustLoss final_loss;
  // Wall time in seconds from the run's start (the process's start on the
  // command line, common/process_start.h; the call's in Python), phase by
  // phase in the order they run, to the report (total_seconds, taken when
  // the report is made). The solve's phases are `solve`'s. OtherSeconds()
  // is the rest, between the phases (the LM's own work beside its three
  // phases, the gauge and the measurements after the solve), so that the
  // phases and it add up to the total.
  double startup_seconds = 0.0;  // to the solve's first work: exec, libraries, arguments, MPI
  double read_seconds = 0.0;     // reading the input, decompression included
  double load_seconds = 0.0;     // the checks and set-up after reading
  double analysis_seconds = 0.0; // the analyse stage: S at the optimum, --covariance
  double write_seconds = 0.0;    // the outputs but the report, each on disk
  double total_seconds = 0.0;
  int64_t peak_memory_bytes = 0;  // main rank
  int64_t problem_bytes = 0;      // main rank's problem arrays before the solve
  // One process: the peak estimated before S's values were allocated
  // (lm/memory_estimate.h); total 0 when not estimated.
  MemoryEstimate memory_estimate;
  int64_t available_memory_bytes = 0;  // when estimated; 0 if unknown
  SolveOnRanksSummary solve;      // ranks == 1: a one-process solve
  // The camera-side unknowns by the kind of their block
  // (problem/parameter_blocks.h), as the solve had them.
  std::array<int64_t, kNumBlockKinds> unknowns_by_kind{};
  // --reject-outliers: the rounds after the first solve (each followed by a
  // solve when it dropped anything).
  double reject_outliers_px = 0.0;
  std::vector<RejectionRound> rejection;
  // With --truth and --reject-outliers: the generator's mismatches
  // (IsTrueOutlier) among the loaded observations, and what was dropped.
  bool has_outlier_truth = false;
  int64_t true_outliers = 0, true_outliers_dropped = 0;
  int64_t true_inliers = 0, true_inliers_dropped = 0;
  // --camera-priors and --gcps: the adjusted block against the survey, and
  // the frame the solve ran in.
  GeoreferenceSummary geo;
  // What held the gauge (camera/gauge_hold.h), as the summary says it.
  std::string gauge;
  // --covariance: how the precision was taken (precision/camera_covariance.h).
  struct Covariance {
    bool computed = false;
    std::string datum;  // "inner" (constraints over the centres) or "absolute"
    bool unit = false;  // for a pixel σ of 1; else scaled by variance_factor
    // σ̂₀² = Σρ / r, r = 2 observations + 3 priors + 3 control points −
    // unknowns (camera side and 3 per point) + the datum's free degrees.
    double variance_factor = 0.0;
    int64_t redundancy = 0;
    double Scale() const { return unit ? 1.0 : variance_factor; }  // the files' factor
    int64_t factor_nonzeros = 0;  // scalars of S's factor, inverted in place
    double inversion_flops = 0.0;
    double factor_seconds = 0.0;  // of `seconds`: to the factor and the datum's solves
    double seconds = 0.0;
    // Each intrinsic group with free parameters: its covariance, scaled as
    // the file's (precision/camera_covariance.h).
    std::vector<IntrinsicsCovariance> intrinsics;
    // The control points' predicted covariance in the solve's frame (the
    // accuracy report's frame), scaled as the file.
    struct ControlPoint {
      std::string name;
      Eigen::Matrix3d covariance;
    };
    std::vector<ControlPoint> control_points;
    // With --point-covariance: the points their observations do not
    // determine (one observation, parallel rays), whose lines are empty.
    int64_t undetermined_points = -1;
    // Images (COLMAP names, else 0-based indices) and intrinsic groups the
    // data do not determine (precision/undetermined_unknowns.h).
    std::vector<std::string> undetermined_images;
    std::vector<int64_t> undetermined_groups;
    std::string error;  // why it failed after the solve (computed false)
  } covariance;
  bool has_truth = false;
  GroundTruthErrors truth;        // against a generated problem's ground truth

  double OtherSeconds() const;
};

// One line per LM iteration, and its header.
std::string IterationLogHeader();
std::string IterationLogLine(const IterationSummary& it);

// The summary, computed once (session/solve_summary.cc): every figure the
// printed summary, --report's JSON and Python's Summary show, as the JSON
// document --report writes.
nlohmann::ordered_json SolveSummary(const SolveReport& report);
std::string SolveReportJson(const SolveReport& report);  // SolveSummary, dumped
// The summary rendered for people (session/solve_summary_text.cc).
void PrintSolveSummary(const nlohmann::ordered_json& summary, std::ostream& out);
void PrintSolveReport(const SolveReport& report, std::ostream& out);

}  // namespace dba
