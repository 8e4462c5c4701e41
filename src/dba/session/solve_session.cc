// One solve in every mode; see solve_session.h.
#include "dba/session/solve_session.h"

#include "dba/problem/point_order.h"

#include <omp.h>

#include <algorithm>
#include <utility>
#include <cstdio>
#include <ostream>
#include <stdexcept>

#include "dba/camera/fov_series_start.h"
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

int ThreadsPerRank(int asked, const Communicator& comm) {
  return asked > 0 ? asked : std::max(1, DefaultThreads() / comm.ranks_on_node());
}

// Whether --resume restarts after a rejection round (the main rank reads the
// checkpoint's header; unreadable: as if so, and Resume says why).
// Collective.
static bool ResumesAfterARound(const SolveOptions& options, Communicator* comm) {
  if (options.resume_path.empty() || options.reject_outliers_px <= 0) return false;
  int32_t round = comm->is_main() ? ReadCheckpointRound(options.resume_path) : 0;
  comm->Broadcast(Traffic::kControl, &round);
  return round != 0;
}

SolveInput LoadInput(const SolveOptions& options, const InputSource& source, Communicator* comm) {
  omp_set_num_threads(ThreadsPerRank(options.lm.num_threads, *comm));
  SolveInput input;
  input.name = options.input;
  // Distributed runs on a binary file: every rank reads its own points and
  // the main rank only the camera side (georeferencing aligns it onto the
  // priors and adds the control points; the ranks move their points by the
  // same similarity). The main rank reads the whole problem instead when
  // control points alone align the block (their first triangulation starts
  // at tie points near their measurements), and when a resume restarts
  // after a rejection round (it cuts the problem down to what the rounds
  // left before handing it out).
  const bool aligned_on_control_points =
      !options.geo.gcps_path.empty() && options.geo.camera_priors_path.empty() &&
      options.resume_path.empty();
  input.source = source;
  input.ranks_read_file = comm->size() > 1 && source.binary() &&
                          !aligned_on_control_points &&
                          !ResumesAfterARound(options, comm);
  if (!comm->is_main()) return input;
  if (input.ranks_read_file) {
    // Checked here, before the solve; every rank holds them fixed in the
    // camera side it reads (the same command line on every rank).
    input.problem = Problem(ReadBinaryCameraSide(options.input));
    ApplyFixings(options.unknowns, &input.problem);
    return input;
  }
  input.problem = LoadSolveInput(source, options.unknowns, &input.names, &input.colmap_cameras);
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

int64_t RefuseNonFiniteResiduals(const std::string& input, const Problem& problem,
                                 std::span<const int64_t> walk) {
  const ResidualScan scan = ScanResiduals(problem, walk);
  if (scan.non_finite == 0) return scan.behind_cameras;
  std::string where;
  for (const ResidualScan::Where& w : scan.first_non_finite) {
    where += (where.empty() ? "" : "; ") + std::string("observation ") +
             std::to_string(w.observation) + " (camera " + std::to_string(w.camera) +
             ", point " + std::to_string(w.point) + ")";
  }
  throw std::runtime_error(input + ": " + std::to_string(scan.non_finite) +
                           " observation(s) have a non-finite reprojection error (nan or inf) at "
                           "the initial parameters, e.g. " + where +
                           "; correct or remove them (a point at a camera centre, or values "
                           "beyond double range)");
}

SetupFingerprint SolveSetup(const SolveOptions& options, const Georeference& geo, bool rigs) {
  SetupFingerprint f;
  const RobustLoss& loss = options.lm.loss;
  f.Add("--loss", LossName(loss.type));
  f.Add("--loss", loss.scale);
  const UnknownsOptions& u = options.unknowns;
  if (rigs && (!u.refine_rig_geometry || !u.held_sensors.empty())) {
    std::vector<int64_t> held = u.held_sensors;
    std::sort(held.begin(), held.end());
    held.erase(std::unique(held.begin(), held.end()), held.end());
    f.Add("--rig-geometry", u.refine_rig_geometry ? "fixed:IDS" : "fixed");
    f.Add("--rig-geometry", held.data(), held.size() * sizeof held[0]);
  }
  for (const CameraCentrePrior& p : geo.priors.priors) {
    f.Add("--camera-priors", &p.image, sizeof p.image);
    f.Add("--camera-priors", p.centre.data(), 3 * sizeof(double));
    f.Add("--camera-priors", p.sigma.data(), 3 * sizeof(double));
  }
  if (!geo.priors.empty()) {
    f.Add("--prior-loss", LossName(geo.priors.loss.type));
    f.Add("--prior-loss", geo.priors.loss.scale);
    if (!geo.priors.lever_arm.isZero(0.0) || geo.priors.refine_lever_arm) {
      f.Add("--lever-arm", geo.priors.lever_arm.data(), 3 * sizeof(double));
    }
    if (geo.priors.refine_lever_arm) f.Add("--refine-lever-arm", 1.0);
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
  lm_.num_threads = ThreadsPerRank(lm_.num_threads, *comm);
  // Every parallel region without a count of its own (loading, the
  // symbolic phase) takes the solve's threads too.
  omp_set_num_threads(lm_.num_threads);
  // Progress of long phases: the main rank, on a terminal, without -q.
  EnableProgress(comm->is_main() && !options.quiet && options.progress);
}

// The stages: prepare (main rank) -> solve (its rounds; every rank) ->
// analyse (ranks alive) -> finish (the ranks end) -> hold the gauge ->
// measure (main rank).
SolveResult SolveSession::Run(SolveInput input) {
  input_ = std::move(input);
  if (comm_->is_main()) Prepare();
  Solve();
  if (comm_->is_main()) {
    Analyse();
    FinishSolve(side_.get());
    side_.reset();
    HoldGauge();
    Measure();
  }
  result_.names = std::move(input_.names);
  result_.ranks_read_file = input_.ranks_read_file;
  result_.source = input_.source;
  return std::move(result_);
}

// The main rank's work before the solve: the input taken over and checked,
// the walk's order and the gauge's reference taken as loaded (before an
// alignment or a resume moves the points), georeferencing, a resume.
void SolveSession::Prepare() {
  Timer load;
  Start(input_);
  // Every rank that reads the file moves its own copy alike (ReadShare).
  const std::vector<FovStartMove> fov = StartFovOutsideSeries(&result_.problem);
  if (!options_.quiet) out_ << DescribeFovStartMoves(fov);
  // The walk's order from the positions as loaded: the same for a solve
  // and its resume (over ranks the shares handed out follow it; ranks that
  // read the file walk their own as read).
  if (!input_.ranks_read_file) {
    load_order_ = PointWalk(result_.problem);
    if (!load_order_.empty() && !options_.quiet) {
      out_ << "points walked in a spatial order (the input's order is scattered); outputs keep "
              "the input's\n";
    }
  }
  if (!input_.ranks_read_file) {
    result_.report.observations_behind_cameras =
        RefuseNonFiniteResiduals(input_.name, result_.problem, load_order_);
  }
  gauge_ = TakeGaugeReference(result_.problem, options_.gauge, input_.names.read_order);
  if (options_.geo.any()) PrepareGeoreferencing();
  if (options_.gauge != GaugeRule::kFree &&
      (!result_.geo.priors.empty() || result_.geo.control_points > 0)) {
    gauge_.hold = GaugeHold::kExternal;
  }
  setup_ = SolveSetup(options_, result_.geo, result_.problem.has_rigs());
  if (!options_.covariance_path.empty()) CheckCovarianceRequest();
  Resume();
  if (!options_.truth_path.empty()) CheckTruthFile(options_.truth_path, result_.report);
  result_.report.load_seconds = load.Seconds();
  PrintStart();
}

// The report's figures of the input; the problem taken over.
void SolveSession::Start(const SolveInput& input) {
  SolveReport& report = result_.report;
  report.input = input.name;
  report.read_seconds = input.read_seconds;
  report.threads = lm_.num_threads;
  report.loss = lm_.loss;
  report.final_loss = lm_.loss;
  report.reject_outliers_px = options_.reject_outliers_px;
  report.linear_solver = lm_.linear_solver;
  report.memory_check = options_.memory_check;
  report.checkpoint_path = options_.checkpoint_path;
  result_.problem = std::move(input_.problem);  // the camera side alone when the ranks read
  if (input.ranks_read_file) {
    const BinaryProblemHeader h = ReadBinaryProblemHeader(input.name);
    report.num_intrinsic_groups = h.num_intrinsics;
    report.num_cameras = h.num_cameras;
    report.num_points = h.num_points;
    report.num_observations = h.num_observations;
    return;
  }
  const Problem& problem = result_.problem;
  report.num_colmap_cameras = input.colmap_cameras.all;
  report.num_colmap_cameras_used = input.colmap_cameras.used;
  report.num_colmap_sensors_not_modelled = input.colmap_cameras.sensors_not_modelled;
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
  if (result_.geo.priors.refine_lever_arm) TakeLeverArm(&*resumed_);
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

// A refined lever arm's 3 values, after the checkpoint's cameras
// (SolveSession::WriteCheckpoint): the solve resumes from them.
void SolveSession::TakeLeverArm(Checkpoint* c) {
  std::vector<double>& x = c->cameras;
  if (x.size() != result_.problem.cameras.size() + 3) {
    throw InputError(options_.resume_path, 0,
                     "written for another input: its camera values do not fit this problem's "
                     "cameras and a lever arm");
  }
  result_.geo.priors.lever_arm = Vec3(x.data() + x.size() - 3);
  x.resize(x.size() - 3);
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
  loaded_observations_ = problem.num_observations();
  ApplyCheckpoint(std::move(*c), options_.resume_path, &problem);
  result_.all_points = problem.points;
  origin_ = IndicesOf(kept);
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
    // A solve the iteration limit ended goes on under a higher limit.
    const auto ended = static_cast<TerminationReason>(resumed_->ended);
    const bool more_iterations =
        ended == TerminationReason::kMaxIterations && o.max_iterations > o.iterations_done;
    if (resumed_->ended >= 0 && !more_iterations) {
      o.ended = LmOptions::Ended{ended, resumed_->cost};
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
  if (const int64_t n = report.num_colmap_sensors_not_modelled; n > 0) {
    out_ << "COLMAP rigs: " << n << (n == 1 ? " sensor that is not a camera (IMU) is" : " sensors that are not cameras (IMU) are")
         << " kept in the model as read, not adjusted\n";
  }
  // Large problems spend a while here before the first iteration line.
  char line[160];
  std::snprintf(line, sizeof line,
                "loaded in %.1f s (read %.1f s, checks %.1f s); building the RCS structure, then "
                "one line per LM iteration\n",
                report.read_seconds + report.load_seconds, report.read_seconds, report.load_seconds);
  out_ << line;
  // One process: the header follows the memory estimate (the symbolic
  // phase's end).
  if (ranks > 1) out_ << IterationLogHeader();
  out_ << std::flush;
}

// The optimum mapped back onto the input's frame where nothing else holds
// the gauge (camera/gauge_hold.h): the cameras, the points left, and with
// rejection every loaded point kept.
void SolveSession::HoldGauge() {
  const Similarity s = GaugeMapping(gauge_, result_.problem);
  const bool identity = s.scale == 1.0 && s.rotation == Mat3::Identity() && s.translation.isZero(0);
  if (!identity) {
    result_.gauge_moved = s;
    MoveCameras(s, &result_.problem);
    MovePoints(s, &result_.problem.points);
    if (result_.kept) MovePoints(s, &result_.all_points, result_.kept->point);
  }
  result_.report.gauge = DescribeGauge(gauge_, s, input_.names.id);
}

// Georeferencing measured (the control points, the last points, out again),
// then the truth.
void SolveSession::Measure() {
  SolveReport& report = result_.report;
  if (!result_.geo.empty()) {
    const LmSummary& lm = report.solve.ba.lm;
    MeasureGeoreference(result_.geo,
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
