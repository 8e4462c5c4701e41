// The solve itself, one code path for every mode: LM, the rounds of outlier
// rejection and the checkpoints over a point side that is local or spread
// over MPI ranks (lm/point_side.h); see solve_session.h.
#include <algorithm>
#include <ostream>
#include <stdexcept>
#include <string>
#include <utility>

#include "dba/common/fault_seam.h"
#include "dba/common/memory.h"
#include "dba/lm/local_point_side.h"
#include "dba/lm/memory_estimate.h"
#include "dba/problem/point_order.h"
#include "dba/session/solve_session.h"

namespace dba {
namespace {

// The points `kept` flags, in their loaded order, from every loaded point.
std::vector<double> KeptPoints(const KeptObservations& kept, const std::vector<double>& all) {
  std::vector<double> points;
  for (size_t k = 0; k < kept.point.size(); ++k) {
    if (kept.point[k]) points.insert(points.end(), &all[kPointSize * k], &all[kPointSize * k + kPointSize]);
  }
  return points;
}

// The ranks' options: the fixings of a .dba each rank reads itself, the
// RCS gathered for a covariance.
DistributedOptions RanksOptions(const SolveOptions& options, bool ranks_read_file) {
  DistributedOptions d = options.distributed;
  d.memory_check = options.memory_check;
  d.lever_arm_row = options.geo.refine_lever_arm;
  // The covariance factors S on the main rank: auto gathers it there.
  if (!options.covariance_path.empty() && d.rcs == DistributedOptions::Rcs::kAuto) {
    d.rcs = DistributedOptions::Rcs::kGather;
  }
  if (ranks_read_file) d.fixings = FixingsOf(options.unknowns);
  return d;
}

}  // namespace

// Main rank: the side, the first solve (unless a checkpoint resumed after a
// rejection round), the rounds, the end. Other ranks: their points served.
void SolveSession::Solve() {
  // A solve resumed after a rejection round starts with the squared loss
  // (unless --reject-keep-loss): the ranks hear it from the main rank.
  int32_t squared = resumed_round_ > 0 && !options_.reject_keep_loss ? 1 : 0;
  if (comm_->size() > 1) comm_->Broadcast(Traffic::kControl, &squared);
  if (!comm_->is_main()) {
    LmOptions o = lm_;
    if (squared) o.loss = RobustLoss();
    ServePoints(comm_, o, RanksOptions(options_, input_.ranks_read_file),
                input_.ranks_read_file ? input_.name : std::string());
    return;
  }
  if (!options_.checkpoint_path.empty()) {
    checkpoints_.emplace(options_.checkpoint_path, options_.checkpoint_every_s,
                         input_.ranks_read_file ? 0 : ProblemFingerprint(result_.problem), setup_,
                         lm_.accepted_done);
  }
  const bool reject = options_.reject_outliers_px > 0;
  if (reject && !options_.truth_path.empty() && comm_->size() == 1 && resumed_round_ <= 0) {
    // The loaded pixels, for the truth (which are mismatches), without the
    // control points' measurements.
    const Problem& p = result_.problem;
    loaded_pixels_.assign(p.obs_pixel.begin(), p.obs_pixel.begin() + 2 * result_.report.num_observations);
  }
  const ParameterBlocks blocks(result_.problem, result_.geo.priors.refine_lever_arm);
  for (int k = 0; k < kNumBlockKinds; ++k) {
    result_.report.unknowns_by_kind[k] = blocks.num_unknowns(static_cast<BlockKind>(k));
  }
  side_ = MakePointSide();
  const IterationHook log = IterationLog(side_.get());
  std::function<void(const RcsSystem&)> check_memory = MemoryCheck();
  if (resumed_round_ <= 0) {
    result_.report.solve.ba = side_->Solve(lm_, result_.geo.priors, log, std::exchange(check_memory, {}));
    KeepLeverArm(result_.report.solve.ba);
  }
  if (reject) RejectionRounds(side_.get(), log, std::move(check_memory));
}

// The optimum in hand, ranks alive, before the gauge is mapped back: the
// analysis sees the RCS there (with the last solve's loss).
void SolveSession::Analyse() {
  if (!analysis_ && options_.covariance_path.empty()) return;
  const Timer timer;
  struct Account {  // the stage's time, however it ends
    const Timer& timer;
    double* seconds;
    ~Account() { *seconds = timer.Seconds(); }
  } account{timer, &result_.report.analysis_seconds};
  LmOptions o = lm_;
  o.loss = result_.report.final_loss;
  side_->AtOptimum(o, result_.geo.priors, [&](const RcsSystem& rcs) {
    if (!options_.covariance_path.empty()) {
      // A covariance that fails does not take the solve with it: the
      // solve's outputs are written, the run fails after them.
      try {
        FaultPoint(0, "covariance", 1);
        TakeCovariance(result_.problem, rcs);
      } catch (const std::runtime_error& e) {
        result_.covariance.reset();
        result_.point_covariance.clear();
        result_.report.covariance = SolveReport::Covariance();
        result_.report.covariance.error = result_.covariance_error = e.what();
      }
    }
    if (analysis_) analysis_(OptimumView{result_.problem, rcs});
  });
}

// A refined lever arm as the solve left it: the next rejection round
// starts from it, the accuracy report measures the priors with it.
void SolveSession::KeepLeverArm(const BundleAdjustSummary& ba) {
  if (result_.geo.priors.refine_lever_arm) result_.geo.priors.lever_arm = ba.lever_arm;
}

// The walk over the problem as the point side gets it (problem/point_order.h),
// from the order taken at the load: through the origin of a problem a
// resume cut down; points added since (control points) last, in their order.
std::vector<int64_t> SolveSession::WalkOverSide() {
  const int64_t n = result_.problem.num_points();
  const int64_t loaded = static_cast<int64_t>(load_order_.size());
  if (loaded == 0) return {};
  std::vector<int64_t> walk;
  if (origin_.point.empty()) {
    walk = std::move(load_order_);
  } else {
    const std::vector<int64_t> place = InversePermutation(load_order_);
    std::vector<std::pair<int64_t, int64_t>> keyed;
    for (int64_t k = 0; k < n; ++k) {
      const int64_t given = origin_.point[k];
      if (given < loaded) keyed.emplace_back(place[given], k);
    }
    std::sort(keyed.begin(), keyed.end());
    for (const auto& [place_of, k] : keyed) walk.push_back(k);
  }
  std::vector<int64_t>().swap(load_order_);
  std::vector<uint8_t> walked(n, 0);
  for (int64_t k : walk) walked[k] = 1;
  for (int64_t k = 0; k < n; ++k) {
    if (!walked[k]) walk.push_back(k);
  }
  return walk;
}

std::unique_ptr<PointSide> SolveSession::MakePointSide() {
  if (comm_->size() == 1) return std::make_unique<LocalPointSide>(&result_.problem, WalkOverSide());
  const DistributedCheckpoints checkpoints{
      checkpoints_ ? &*checkpoints_ : nullptr,
      input_.ranks_read_file && resumed_ ? &*resumed_ : nullptr, options_.resume_path};
  std::optional<std::vector<int64_t>> walk;
  if (!input_.ranks_read_file) walk = WalkOverSide();
  auto ranks = std::make_unique<DistributedPointSide>(
      comm_, lm_, RanksOptions(options_, input_.ranks_read_file),
      input_.ranks_read_file ? input_.name : std::string(), &result_.problem, checkpoints,
      result_.geo.alignment, walk);
  ranks_ = ranks.get();
  return ranks;
}

// The log line of every iteration, and the checkpoints after accepted ones
// (and always the one that ends a solve, its last step accepted or not).
SolveSession::IterationHook SolveSession::IterationLog(PointSide* side) {
  return [this, side](const IterationSummary& it) {
    if (!options_.quiet) out_ << IterationLogLine(it) << std::flush;
    if (checkpoints_ && checkpoints_->Due(it.step_accepted, it.ends_solve)) WriteCheckpoint(it, side);
  };
}

// The parameters where they are; on ranks the points gathered; after a
// rejection round every loaded point and what is left.
void SolveSession::WriteCheckpoint(const IterationSummary& it, PointSide* side) {
  Checkpoint state;
  state.iterations = it.iteration;
  state.lambda = it.next_lambda;
  // A rejected last step left the parameters (and the cost) where the
  // iteration started.
  state.cost = it.step_accepted ? it.candidate_cost : it.cost;
  state.ended = it.ends_solve ? static_cast<int32_t>(it.termination) : -1;
  state.round = static_cast<int32_t>(rounds_.size());
  for (const RejectionRound& r : rounds_) {
    state.rounds.push_back({r.observations_dropped, r.points_dropped, r.points_small_angle,
                            r.observations_left, r.points_left});
  }
  std::vector<double> cameras;  // in the input's order (a walked solve renumbers them)
  side->AllCameras(&cameras);
  // A refined lever arm: its 3 values after the cameras (SolveSession::Resume).
  if (result_.geo.priors.refine_lever_arm) {
    cameras.insert(cameras.end(), it.lever_arm.data(), it.lever_arm.data() + 3);
  }
  if (rounds_.empty()) {
    std::vector<double> points;  // in the input's order (a solve walks its own)
    side->AllPoints(&points);
    checkpoints_->Write(state, cameras, points);
    return;
  }
  KeptObservations kept;
  std::vector<double> points;
  LoadedKeptAndPoints(side, &kept, &points);
  checkpoints_->Write(state, cameras, points, kept.observation, kept.point);
}

// What the side left and its points, in the problem as loaded (through the
// origin of a problem a resume had cut down already).
void SolveSession::LoadedKeptAndPoints(PointSide* side, KeptObservations* kept,
                                       std::vector<double>* points) {
  KeptObservations given = side->Kept();
  std::vector<double> given_points;
  side->AllPoints(&given_points);
  if (origin_.point.empty()) {
    *kept = std::move(given);
    *points = std::move(given_points);
    return;
  }
  *points = result_.all_points;  // the checkpoint's, for what was dropped before
  kept->observation.assign(loaded_observations_, 0);
  kept->point.assign(points->size() / kPointSize, 0);
  for (size_t o = 0; o < given.observation.size(); ++o) {
    kept->observation[origin_.observation[o]] = given.observation[o];
  }
  for (size_t k = 0; k < given.point.size(); ++k) {
    kept->point[origin_.point[k]] = given.point[k];
    std::copy_n(&given_points[kPointSize * k], kPointSize, &(*points)[kPointSize * origin_.point[k]]);
  }
}

// One process, after the symbolic phase, before S's values: the peak
// estimated, and the solve refused where it would not fit. (Each rank
// checks its own: cluster/distributed_solve.cc.)
std::function<void(const RcsSystem&)> SolveSession::MemoryCheck() {
  if (comm_->size() > 1) return {};
  return [this](const RcsSystem& structure) {
    MemoryCheckOptions check;
    check.refuse = options_.memory_check;
    check.covariance = !options_.covariance_path.empty();
    SolveReport& report = result_.report;
    EstimateAndCheckMemory(result_.problem, structure, lm_, check,
                           [&](const MemoryEstimate& estimate, int64_t have) {
      report.memory_estimate = estimate;
      report.available_memory_bytes = have;
      if (options_.quiet) return;
      out_ << "memory estimate " << estimate.Describe()
           << (have >= 0 ? "; available " + FormatBytes(have + estimate.resident) : std::string())
           << "\n" << IterationLogHeader() << std::flush;
    });
  };
}

// A rejection that left nothing to adjust: refused before any output is
// written (a BAL file "49 0 0" is one no reader takes).
static void RefuseAnEmptyProblem(const std::vector<RejectionRound>& rounds) {
  const RejectionRound& last = rounds.back();
  if (last.observations_left > 0 && last.points_left > 0) return;
  int64_t observations = 0, points = 0, for_angle = 0;
  for (const RejectionRound& r : rounds) {
    observations += r.observations_dropped;
    points += r.points_dropped;
    for_angle += r.points_small_angle;
  }
  throw std::runtime_error(
      "outlier rejection dropped every observation (" + std::to_string(observations) +
      " observations and " + std::to_string(points) + " points, " + std::to_string(for_angle) +
      " of them for their triangulation angle, in " + std::to_string(rounds.size()) +
      " round(s)); nothing is left to adjust and nothing was written: raise "
      "--reject-outliers or lower --min-triangulation-angle");
}

// Rounds of --reject-outliers after the first solve, each checked by the
// guard (lm/rejection_guard.h) before the solve after it. A checkpoint
// written after a round resumes in the solve after it.
void SolveSession::RejectionRounds(PointSide* side, const IterationHook& log,
                                   std::function<void(const RcsSystem&)> check_memory) {
  SolveReport& report = result_.report;
  const RejectionCriteria criteria{options_.reject_outliers_px,
                                   options_.min_triangulation_angle_deg};
  bool resumed_round = resumed_round_ > 0;
  bool first_solve = resumed_round;  // no solve yet in this run
  // The solve before a round: the first, or the one after the last round.
  SolveBeforeRound before{report.solve.ba.lm.termination, lm_.loss.trivial()};
  report.rejection = RunRejectionRounds(
      [&] {
        PoseObservations poses;
        rounds_.push_back(
            side->DropOutliers(criteria, lm_.num_threads, options_.reject_keep_loss, &poses));
        CheckRejectionRound({options_.reject_max_share}, criteria.max_error_px,
                            static_cast<int>(rounds_.size()), rounds_.back(), poses,
                            result_.problem, before);
        RefuseAnEmptyProblem(rounds_);
        return rounds_.back();
      },
      [&] {
        const LmOptions o = RoundOptions(resumed_round);
        if (checkpoints_ && !resumed_round) checkpoints_->StartRound();
        resumed_round = false;
        const BundleAdjustSummary s =
            side->Solve(o, result_.geo.priors, log, std::exchange(check_memory, {}));
        KeepLeverArm(s);
        before = {s.lm.termination, o.loss.trivial()};
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
}

// What is left and every loaded point; the ranks ended (their figures and
// final points collected).
void SolveSession::FinishSolve(PointSide* side) {
  side->EndSolves();  // the problem back in the order it was given
  SolveReport& report = result_.report;
  if (checkpoints_) report.checkpoints_written = checkpoints_->written();
  if (options_.reject_outliers_px > 0) {
    result_.kept.emplace();
    LoadedKeptAndPoints(side, &*result_.kept, &result_.all_points);
  }
  if (ranks_ != nullptr) {
    const bool collect = !options_.output.empty() || !options_.truth_path.empty() ||
                         !options_.ply_path.empty() || !options_.geo.gcps_path.empty();
    ranks_->Finish(collect && !result_.kept, &report.solve);
    report.memory_estimate = report.solve.memory_estimate;
    // The loaded pixels, for the truth: the main rank handed its
    // observations out.
    if (!options_.truth_path.empty()) {
      loaded_pixels_ = LoadSolveInput(input_.source, options_.unknowns).obs_pixel;
    }
  }
  if (result_.kept && comm_->size() > 1) {
    result_.problem.points = KeptPoints(*result_.kept, result_.all_points);
  }
}

}  // namespace dba
