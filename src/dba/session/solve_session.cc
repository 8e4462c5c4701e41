// One solve in every mode; see solve_session.h.
#include "dba/session/solve_session.h"

#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <ostream>
#include <stdexcept>

#include "dba/camera/observation_residual.h"
#include "dba/cluster/distributed_solve.h"
#include "dba/common/error.h"
#include "dba/common/memory.h"
#include "dba/common/progress.h"
#include "dba/common/timer.h"
#include "dba/io/binary_problem.h"
#include "dba/io/read_problem.h"
#include "dba/lm/bundle_adjust.h"
#include "dba/lm/memory_estimate.h"
#include "dba/session/truth_comparison.h"
#include "dba/synthetic/ground_truth.h"

namespace dba {
namespace {

// Writes the problem's points into `all` at their loaded positions.
void ScatterPoints(const Problem& problem, const OriginalIndices& original,
                   std::vector<double>* all) {
  for (size_t k = 0; k < original.point.size(); ++k) {
    for (int d = 0; d < 3; ++d) (*all)[3 * original.point[k] + d] = problem.points[3 * k + d];
  }
}

// The flags of what `original` still holds, over `observations` and
// `points` as loaded.
KeptObservations KeptOf(const OriginalIndices& original, int64_t observations, int64_t points) {
  KeptObservations kept;
  kept.observation.assign(observations, 0);
  for (int64_t o : original.observation) kept.observation[o] = 1;
  kept.point.assign(points, 0);
  for (int64_t k : original.point) kept.point[k] = 1;
  return kept;
}

// The points `kept` flags, in their loaded order, from every loaded point.
std::vector<double> KeptPoints(const KeptObservations& kept, const std::vector<double>& all) {
  std::vector<double> points;
  for (size_t k = 0; k < kept.point.size(); ++k) {
    if (kept.point[k]) points.insert(points.end(), &all[kPointSize * k], &all[kPointSize * k + kPointSize]);
  }
  return points;
}

}  // namespace

SolveInput LoadInput(const SolveOptions& options, const Communicator& comm) {
  SolveInput input;
  input.name = options.input;
  // Distributed runs on a binary file: every rank reads its own points;
  // not when georeferencing, which moves the whole block and adds control
  // points before the solve (the main rank reads it all and hands it out).
  input.ranks_read_file = comm.size() > 1 && IsBinaryProblem(options.input) && !options.geo.any();
  if (!comm.is_main()) return input;
  if (input.ranks_read_file) {
    // Checked here, before the solve; every rank holds them fixed in the
    // camera side it reads (the same command line on every rank).
    CheckedFixings(options.unknowns, ReadBinaryCameraSide(options.input));
    return input;
  }
  const bool names = options.geo.any() || !options.geo.camera_centres_path.empty();
  input.problem = LoadSolveInput(options.input, options.unknowns, names ? &input.names : nullptr);
  return input;
}

std::string RejectionRoundLine(const RejectionCriteria& criteria, int r,
                               const RejectionRound& round) {
  char line[256];
  std::snprintf(line, sizeof line,
                "outlier rejection round %d (|r| > %g px, angle < %g deg): dropped %lld "
                "observations and %lld points (%lld for their angle); %lld observations, %lld "
                "points left\n",
                r, criteria.max_error_px, criteria.min_triangulation_angle_deg,
                static_cast<long long>(round.observations_dropped),
                static_cast<long long>(round.points_dropped),
                static_cast<long long>(round.points_small_angle),
                static_cast<long long>(round.observations_left),
                static_cast<long long>(round.points_left));
  return line;
}

void RefuseNonFiniteResiduals(const std::string& input, const Problem& problem) {
  const NonFiniteResiduals bad = FindNonFiniteResiduals(problem);
  if (bad.count == 0) return;
  std::string where;
  for (const NonFiniteResiduals::Where& w : bad.first) {
    where += (where.empty() ? "" : "; ") + std::string("observation ") +
             std::to_string(w.observation) + " (camera " + std::to_string(w.camera) +
             ", point " + std::to_string(w.point) + ")";
  }
  throw std::runtime_error(input + ": " + std::to_string(bad.count) +
                           " observation(s) have a non-finite reprojection error (nan or inf) at "
                           "the initial parameters, e.g. " + where +
                           "; correct or remove them (a point at a camera centre, or values "
                           "beyond double range)");
}

SolveSession::SolveSession(const SolveOptions& options, Communicator* comm, std::ostream& log)
    : options_(options), comm_(comm), out_(log), lm_(options.lm) {
  if (lm_.num_threads == 0) lm_.num_threads = std::max(1, DefaultThreads() / comm->ranks_on_node());
  // Every parallel region without a count of its own (loading, the
  // symbolic phase) takes the solve's threads too.
  omp_set_num_threads(lm_.num_threads);
  // Progress of long phases: the main rank, on a terminal, without -q.
  EnableProgress(comm->is_main() && !options.quiet && options.progress);
}

SolveResult SolveSession::Run(SolveInput input) {
  input_ = std::move(input);
  if (comm_->is_main()) {
    Timer load;
    Start(input_);
    Resume();
    if (!input_.ranks_read_file) RefuseNonFiniteResiduals(input_.name, result_.problem);
    if (!options_.truth_path.empty()) CheckTruthFile(options_.truth_path, result_.report);
    if (options_.geo.any()) PrepareGeoreferencing();
    result_.report.load_seconds = load.Seconds();
    PrintStart();
  }
  if (comm_->size() == 1) {
    SolveInOneProcess();
  } else {
    SolveOnRanks();
  }
  if (comm_->is_main()) Measure();
  result_.names = std::move(input_.names);
  result_.ranks_read_file = input_.ranks_read_file;
  return std::move(result_);
}

// The report's figures of the input; the problem taken over.
void SolveSession::Start(const SolveInput& input) {
  SolveReport& report = result_.report;
  report.input = input.name;
  report.threads = lm_.num_threads;
  report.loss = lm_.loss;
  report.final_loss = lm_.loss;
  report.reject_outliers_px = options_.reject_outliers_px;
  if (input.ranks_read_file) {
    const BinaryProblemHeader h = ReadBinaryProblemHeader(input.name);
    report.num_intrinsic_groups = h.num_intrinsics;
    report.num_cameras = h.num_cameras;
    report.num_points = h.num_points;
    report.num_observations = h.num_observations;
    return;
  }
  result_.problem = std::move(input_.problem);
  const Problem& problem = result_.problem;
  report.num_cameras = problem.num_images();
  report.num_intrinsic_groups = problem.num_groups();
  report.num_points = problem.num_points();
  report.num_observations = problem.num_observations();
  report.problem_bytes = problem.MemoryBytes();
}

// --resume: the checkpoint's parameters and LM state (spread over the
// ranks, the problem is checked against it there).
void SolveSession::Resume() {
  if (options_.resume_path.empty()) return;
  resumed_ = ReadCheckpoint(options_.resume_path);
  if (!input_.ranks_read_file) {
    ApplyCheckpoint(std::move(*resumed_), options_.resume_path, &result_.problem);
  }
  lm_.initial_lambda = resumed_->lambda;
  lm_.iterations_done = static_cast<int>(resumed_->iterations);
  lm_.accepted_done = static_cast<int>(resumed_->accepted);
  out_ << "resumed from " << options_.resume_path << " after LM iteration "
       << resumed_->iterations << "\n";
}

void SolveSession::PrepareGeoreferencing() {
  result_.geo = PrepareGeoreference(options_.geo, input_.names, &result_.problem,
                                    &result_.report.geo, out_);
}

void SolveSession::PrintStart() {
  const SolveReport& report = result_.report;
  const int ranks = comm_->size();
  out_ << "dba solve " << input_.name << ": " << report.num_cameras
       << (report.num_intrinsic_groups > 0
               ? " images, " + std::to_string(report.num_intrinsic_groups) + " intrinsic groups, "
               : " cameras, ")
       << report.num_points << " points, " << report.num_observations << " observations, "
       << ranks << (ranks == 1 ? " rank, " : " ranks, ") << lm_.num_threads << " threads"
       << (ranks == 1 ? "" : " per rank") << "\n";
  if (options_.quiet) return;
  // Large problems spend a while here before the first iteration line.
  char line[160];
  std::snprintf(line, sizeof line,
                "loaded in %.1f s; building the RCS structure, then one line per LM iteration\n",
                report.load_seconds);
  out_ << line;
  // One process: the header follows the memory estimate (the symbolic
  // phase's end).
  if (ranks > 1) out_ << IterationLogHeader();
  out_ << std::flush;
}

// The log line of every iteration, and the checkpoints after accepted ones
// (one process: the parameters where the workers update them; a
// distributed solve gathers its points itself). A binary input spread over
// the ranks gets its fingerprint once the ranks hold it.
std::function<void(const IterationSummary&)> SolveSession::IterationLog() {
  if (comm_->is_main() && !options_.checkpoint_path.empty()) {
    checkpoints_.emplace(options_.checkpoint_path, options_.checkpoint_every_s,
                         input_.ranks_read_file ? 0 : ProblemFingerprint(result_.problem),
                         lm_.accepted_done);
  }
  return [this](const IterationSummary& it) {
    if (!options_.quiet) out_ << IterationLogLine(it) << std::flush;
    if (comm_->size() == 1 && checkpoints_ && checkpoints_->Due(it.step_accepted)) {
      checkpoints_->Write(it.iteration, it.next_lambda, it.candidate_cost, result_.problem.cameras,
                          result_.problem.points);
    }
  };
}

void SolveSession::SolveInOneProcess() {
  SolveReport& report = result_.report;
  Problem& problem = result_.problem;
  const auto log = IterationLog();
  if (options_.reject_outliers_px > 0) {
    original_ = OriginalIndices::Identity(problem);
    if (!options_.truth_path.empty()) {  // without the control points' measurements
      loaded_pixels_.assign(problem.obs_pixel.begin(),
                            problem.obs_pixel.begin() + 2 * report.num_observations);
    }
  }
  // After the symbolic phase, before S's values: the peak estimated, and
  // the solve refused where it would not fit.
  auto check_memory = [&](const RcsSystem& structure) {
    report.memory_estimate =
        EstimateSolveMemory(problem, structure, lm_, CurrentResidentBytes(), PeakResidentBytes());
    report.available_memory_bytes = AvailableMemoryBytes();
    if (!options_.quiet) {
      const int64_t have = report.available_memory_bytes;
      out_ << "memory estimate " << report.memory_estimate.Describe()
           << (have > 0 ? "; available " + FormatBytes(have + report.memory_estimate.resident)
                        : std::string())
           << "\n" << IterationLogHeader() << std::flush;
    }
    if (options_.memory_check) {
      CheckMemoryFits(report.memory_estimate, report.available_memory_bytes);
    }
  };
  report.solve.ba = BundleAdjust(lm_, &problem, log, check_memory, &result_.geo.priors);
  if (options_.reject_outliers_px > 0) RejectOutlierRoundsInOneProcess(log);
}

// Rounds of --reject-outliers after the first solve, in one process: what
// is left and every loaded point (the kept ones adjusted) in the result.
void SolveSession::RejectOutlierRoundsInOneProcess(
    const std::function<void(const IterationSummary&)>& log) {
  SolveReport& report = result_.report;
  Problem& problem = result_.problem;
  const RejectionCriteria criteria{options_.reject_outliers_px,
                                   options_.min_triangulation_angle_deg};
  LmOptions resolve = lm_;
  if (!options_.reject_keep_loss) resolve.loss = RobustLoss();
  std::vector<double>& all_points = result_.all_points;
  all_points = problem.points;
  // What the solve started from, control points included (Measure takes
  // them out of the flags again).
  const int64_t observations = problem.num_observations();
  report.rejection = RunRejectionRounds(
      [&] {
        ScatterPoints(problem, original_, &all_points);
        return DropOutliers(criteria, resolve.num_threads, &problem, &original_);
      },
      [&] {
        AppendSolve(BundleAdjust(resolve, &problem, log, {}, &result_.geo.priors), &report.solve.ba);
        report.final_loss = resolve.loss;
      },
      [&](int r, const RejectionRound& round) {
        out_ << RejectionRoundLine(criteria, r, round) << std::flush;
      });
  ScatterPoints(problem, original_, &all_points);
  result_.kept = KeptOf(original_, observations, static_cast<int64_t>(all_points.size() / kPointSize));
}

void SolveSession::SolveOnRanks() {
  SolveReport& report = result_.report;
  const bool main = comm_->is_main();
  DistributedOptions distributed = options_.distributed;
  distributed.memory_check = options_.memory_check;
  if (input_.ranks_read_file) {
    distributed.fixings = Fixings{options_.unknowns.fixed_images, {}};
    for (const IntrinsicFixing& x : options_.unknowns.fixed_intrinsics) {
      if (!x.names.empty()) distributed.fixings.intrinsics.push_back(x);
    }
  }
  const RejectionCriteria criteria{options_.reject_outliers_px,
                                   options_.min_triangulation_angle_deg};
  distributed.reject_outliers = options_.reject_outliers_px > 0;
  distributed.rejection = criteria;
  distributed.reject_keep_loss = options_.reject_keep_loss;
  distributed.priors = result_.geo.priors;
  DistributedHooks hooks;
  hooks.on_iteration = IterationLog();
  hooks.on_rejection_round = [&](int r, const RejectionRound& round) {
    out_ << RejectionRoundLine(criteria, r, round) << std::flush;
  };
  hooks.checkpoints = {checkpoints_ ? &*checkpoints_ : nullptr,
                       input_.ranks_read_file && resumed_ ? &*resumed_ : nullptr,
                       options_.resume_path};
  const bool collect_points = !options_.output.empty() || !options_.truth_path.empty() ||
                              !options_.ply_path.empty() || !options_.geo.gcps_path.empty();
  report.solve = DistributedBundleAdjust(comm_, lm_, distributed,
                                         input_.ranks_read_file ? input_.name : std::string(),
                                         collect_points, &result_.problem, hooks);
  report.memory_estimate = report.solve.memory_estimate;
  if (!main) return;
  if (distributed.reject_outliers) {
    // As one process leaves it: the points left in `problem`, every loaded
    // point in all_points, what is left flagged in kept.
    report.rejection = report.solve.rejection;
    if (report.rejection.front().observations_dropped > 0 && !options_.reject_keep_loss) {
      report.final_loss = RobustLoss();
    }
    result_.kept = report.solve.kept;
    result_.all_points.swap(result_.problem.points);
    if (!result_.all_points.empty()) {
      result_.problem.points = KeptPoints(*result_.kept, result_.all_points);
    }
  }
  // The loaded pixels, for the truth (which are mismatches): read again,
  // the main rank handed its observations out.
  if (!options_.truth_path.empty()) {
    loaded_pixels_ = LoadSolveInput(options_.input, options_.unknowns).obs_pixel;
  }
}

// Georeferencing measured (the control points, the last points, out again),
// then the truth.
void SolveSession::Measure() {
  SolveReport& report = result_.report;
  if (!result_.geo.empty()) {
    const LmSummary& lm = report.solve.ba.lm;
    MeasureGeoreference(options_.geo, result_.geo,
                        {lm.final_cost, lm.num_observations, report.solve.ba.rcs.camera_unknowns,
                         report.num_points},
                        &result_.problem, &report.geo);
    if (result_.kept) {
      result_.all_points.resize(kPointSize * report.num_points);
      result_.kept->point.resize(report.num_points);
      result_.kept->observation.resize(report.num_observations);
    }
  }
  if (!options_.truth_path.empty()) CompareWithTruth();
}

// With outlier rejection the truth is compared in the loaded numbering,
// over the points left (and their observations in the truth). The
// generated mismatches are left out of the RMS to the noise-free pixels
// (their noise-free pixel is not what was matched).
void SolveSession::CompareWithTruth() {
  SolveReport& report = result_.report;
  const Problem& problem = result_.problem;
  const std::vector<double>& points = result_.kept ? result_.all_points : problem.points;
  std::vector<uint8_t> point_kept;
  if (result_.kept) {
    CountTrueOutliers(ReadProblem(options_.truth_path), loaded_pixels_, result_.kept->observation,
                      &report);
    point_kept = result_.kept->point;
  }
  const std::vector<double>& pixels = loaded_pixels_.empty() ? problem.obs_pixel : loaded_pixels_;
  report.truth = CompareWithGroundTruthFile(options_.truth_path, problem.cameras, points,
                                            problem.model, point_kept, pixels,
                                            options_.truth_absolute);
  report.has_truth = true;
}

}  // namespace dba
