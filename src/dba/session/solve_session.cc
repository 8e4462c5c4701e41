// One solve in every mode; see solve_session.h.
#include "dba/session/solve_session.h"

#include <omp.h>

#include <algorithm>
#include <utility>
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

SetupFingerprint SolveSetup(const SolveOptions& options, const Georeference& geo) {
  SetupFingerprint f;
  const RobustLoss& loss = options.lm.loss;
  f.Add("--loss", LossName(loss.type));
  f.Add("--loss", loss.scale);
  for (const CameraCentrePrior& p : geo.priors.priors) {
    f.Add("--camera-priors", &p.image, sizeof p.image);
    f.Add("--camera-priors", p.centre.data(), 3 * sizeof(double));
    f.Add("--camera-priors", p.sigma.data(), 3 * sizeof(double));
  }
  if (!geo.priors.empty()) {
    f.Add("--prior-loss", LossName(geo.priors.loss.type));
    f.Add("--prior-loss", geo.priors.loss.scale);
  }
  for (const GroundControlPoint& p : geo.gcps.points) {
    f.Add("--gcps", p.name);
    f.Add("--gcps", p.position.data(), 3 * sizeof(double));
    f.Add("--gcps", p.sigma.data(), 3 * sizeof(double));
    f.Add("--gcps", p.control ? 1.0 : 0.0);
    for (const auto& m : p.measurements) {
      f.Add("--gcps", &m.image, sizeof m.image);
      f.Add("--gcps", m.pixel.data(), 2 * sizeof(double));
    }
  }
  if (options.reject_outliers_px > 0) {
    f.Add("--reject-outliers", options.reject_outliers_px);
    f.Add("--min-triangulation-angle", options.min_triangulation_angle_deg);
    f.Add("--reject-keep-loss", options.reject_keep_loss ? 1.0 : 0.0);
  }
  return f;
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
    if (!input_.ranks_read_file) RefuseNonFiniteResiduals(input_.name, result_.problem);
    if (options_.geo.any()) PrepareGeoreferencing();
    setup_ = SolveSetup(options_, result_.geo);
    Resume();
    if (!options_.truth_path.empty()) CheckTruthFile(options_.truth_path, result_.report);
    result_.report.load_seconds = load.Seconds();
    PrintStart();
  }
  if (comm_->size() == 1) {
    SolveInOneProcess();
  } else {
    if (options_.reject_outliers_px > 0 &&
        (!options_.checkpoint_path.empty() || !options_.resume_path.empty())) {
      throw UsageError("--checkpoint and --resume with --reject-outliers run in one process: on "
                       "ranks the kept observations are not gathered into checkpoints yet");
    }
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

// --resume: the checkpoint's setup against this run's, its parameters
// (spread over the ranks, the problem is checked against it there), the
// rejection it had done, and its LM state.
void SolveSession::Resume() {
  if (options_.resume_path.empty()) return;
  resumed_ = ReadCheckpoint(options_.resume_path);
  CheckCheckpointSetup(*resumed_, options_.resume_path, setup_);
  if (resumed_->round > 0 && options_.reject_outliers_px <= 0) {
    throw UsageError("--resume " + options_.resume_path + ": written after " +
                     std::to_string(resumed_->round) + " rounds of --reject-outliers");
  }
  if (!input_.ranks_read_file) {
    if (resumed_->round > 0) {
      ResumeRejection(&*resumed_);
    } else {
      ApplyCheckpoint(std::move(*resumed_), options_.resume_path, &result_.problem);
    }
  }
  resumed_round_ = resumed_->round;
  if (resumed_round_ == 0) lm_ = RoundOptions(true);
  out_ << "resumed from " << options_.resume_path << " after LM iteration "
       << resumed_->iterations
       << (resumed_->round > 0 ? " of the solve after rejection round " +
                                     std::to_string(resumed_->round)
                               : std::string())
       << (resumed_->ended >= 0 ? ", which had ended the solve" : "") << "\n";
}

// A checkpoint written after rejection rounds: every loaded point and what
// was left, the problem cut down to it as the rounds left it.
void SolveSession::ResumeRejection(Checkpoint* c) {
  Problem& problem = result_.problem;
  KeptObservations kept{std::move(c->kept_observations), std::move(c->kept_points)};
  if (static_cast<int64_t>(kept.observation.size()) != problem.num_observations() ||
      static_cast<int64_t>(kept.point.size()) != problem.num_points()) {
    throw InputError(options_.resume_path, 0, "written for another input: its kept flags "
                                              "do not fit this problem's observations");
  }
  solve_observations_ = problem.num_observations();
  ApplyCheckpoint(std::move(*c), options_.resume_path, &problem);
  result_.all_points = problem.points;
  original_ = IndicesOf(kept);
  KeepOnly(kept, &problem);
  for (const auto& r : c->rounds) rounds_.push_back({r[0], r[1], r[2], r[3], r[4]});
}

// The LM options of a solve: the first round's (lm_ as configured), or a
// round after a rejection (the squared loss unless --reject-keep-loss);
// with the resumed checkpoint's state when it is the round it resumes in.
LmOptions SolveSession::RoundOptions(bool resumed_round) const {
  LmOptions o = options_.lm;
  o.num_threads = lm_.num_threads;
  if (rounds_.size() > 0 && !options_.reject_keep_loss) o.loss = RobustLoss();
  if (resumed_round && resumed_) {
    o.initial_lambda = resumed_->lambda;
    o.iterations_done = static_cast<int>(resumed_->iterations);
    o.accepted_done = static_cast<int>(resumed_->accepted);
    if (resumed_->ended >= 0) {
      o.ended = LmOptions::Ended{static_cast<TerminationReason>(resumed_->ended), resumed_->cost};
    }
  }
  return o;
}

void SolveSession::PrepareGeoreferencing() {
  // A resumed solve's parameters are aligned already: the checkpoint holds
  // them after the alignment.
  result_.geo = PrepareGeoreference(options_.geo, input_.names, &result_.problem,
                                    &result_.report.geo, out_, options_.resume_path.empty());
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
// (and always the one that ends a solve). A binary input spread over the
// ranks gets its fingerprint once the ranks hold it.
SolveSession::IterationHook SolveSession::IterationLog() {
  if (comm_->is_main() && !options_.checkpoint_path.empty()) {
    checkpoints_.emplace(options_.checkpoint_path, options_.checkpoint_every_s,
                         input_.ranks_read_file ? 0 : ProblemFingerprint(result_.problem), setup_,
                         lm_.accepted_done);
  }
  return [this](const IterationSummary& it) {
    if (!options_.quiet) out_ << IterationLogLine(it) << std::flush;
    if (comm_->size() == 1 && checkpoints_ && checkpoints_->Due(it.step_accepted, it.ends_solve)) {
      WriteCheckpoint(it);
    }
  };
}

// One process: the parameters where the workers update them; after a
// rejection round every loaded point (the kept ones scattered back) and
// what is left.
void SolveSession::WriteCheckpoint(const IterationSummary& it) {
  Checkpoint state;
  state.iterations = it.iteration;
  state.lambda = it.next_lambda;
  state.cost = it.candidate_cost;
  state.ended = it.ends_solve ? static_cast<int32_t>(it.termination) : -1;
  state.round = static_cast<int32_t>(rounds_.size());
  for (const RejectionRound& r : rounds_) {
    state.rounds.push_back({r.observations_dropped, r.points_dropped, r.points_small_angle,
                            r.observations_left, r.points_left});
  }
  const Problem& problem = result_.problem;
  if (rounds_.empty()) {
    checkpoints_->Write(state, problem.cameras, problem.points);
    return;
  }
  ScatterPoints(problem, original_, &result_.all_points);
  const KeptObservations kept = KeptFlags(original_, solve_observations_,
                                          static_cast<int64_t>(result_.all_points.size() / kPointSize));
  checkpoints_->Write(state, problem.cameras, result_.all_points, kept.observation, kept.point);
}

// After the symbolic phase, before S's values: the peak estimated, and the
// solve refused where it would not fit.
std::function<void(const RcsSystem&)> SolveSession::MemoryCheck() {
  return [this](const RcsSystem& structure) {
    SolveReport& report = result_.report;
    report.memory_estimate = EstimateSolveMemory(result_.problem, structure, lm_,
                                                 CurrentResidentBytes(), PeakResidentBytes());
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
}

void SolveSession::SolveInOneProcess() {
  SolveReport& report = result_.report;
  Problem& problem = result_.problem;
  const IterationHook log = IterationLog();
  std::function<void(const RcsSystem&)> check_memory = MemoryCheck();
  const bool reject = options_.reject_outliers_px > 0;
  if (reject && resumed_round_ <= 0) {
    original_ = OriginalIndices::Identity(problem);
    solve_observations_ = problem.num_observations();
  }
  if (reject && !options_.truth_path.empty()) {  // without the control points' measurements
    if (resumed_round_ <= 0) {
      loaded_pixels_.assign(problem.obs_pixel.begin(),
                            problem.obs_pixel.begin() + 2 * report.num_observations);
    } else {  // a resumed problem is cut down already
      loaded_pixels_ = LoadSolveInput(options_.input, options_.unknowns).obs_pixel;
    }
  }
  if (resumed_round_ <= 0) {
    report.solve.ba = BundleAdjust(lm_, &problem, log, check_memory, &result_.geo.priors);
    check_memory = {};
  }
  if (reject) RejectOutlierRoundsInOneProcess(log, check_memory);
}

// Rounds of --reject-outliers after the first solve, in one process: what
// is left and every loaded point (the kept ones adjusted) in the result. A
// checkpoint written after a round resumes in the solve after it.
void SolveSession::RejectOutlierRoundsInOneProcess(
    const IterationHook& log, std::function<void(const RcsSystem&)> check_memory) {
  SolveReport& report = result_.report;
  Problem& problem = result_.problem;
  const RejectionCriteria criteria{options_.reject_outliers_px,
                                   options_.min_triangulation_angle_deg};
  std::vector<double>& all_points = result_.all_points;
  if (resumed_round_ <= 0) all_points = problem.points;
  bool resumed_round = resumed_round_ > 0;
  bool first_solve = resumed_round;  // no solve yet in this run
  report.rejection = RunRejectionRounds(
      [&] {
        ScatterPoints(problem, original_, &all_points);
        rounds_.push_back(DropOutliers(criteria, lm_.num_threads, &problem, &original_));
        return rounds_.back();
      },
      [&] {
        const LmOptions o = RoundOptions(resumed_round);
        if (checkpoints_ && !resumed_round) checkpoints_->StartRound();
        resumed_round = false;
        const BundleAdjustSummary s =
            BundleAdjust(o, &problem, log, std::exchange(check_memory, {}), &result_.geo.priors);
        if (first_solve) {
          report.solve.ba = s;
        } else {
          AppendSolve(s, &report.solve.ba);
        }
        first_solve = false;
        report.final_loss = o.loss;
      },
      [&](int r, const RejectionRound& round) {
        out_ << RejectionRoundLine(criteria, r, round) << std::flush;
      },
      rounds_);
  ScatterPoints(problem, original_, &all_points);
  result_.kept = KeptFlags(original_, solve_observations_,
                           static_cast<int64_t>(all_points.size() / kPointSize));
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
