// Distributed bundle adjustment; see distributed_solve.h.
#include "dba/cluster/distributed_solve.h"

#include <stdexcept>
#include <string>
#include <utility>

#include "dba/camera/fov_series_start.h"
#include "dba/common/memory.h"
#include "dba/common/timer.h"
#include "dba/io/binary_problem.h"
#include "dba/lm/solve_with_priors.h"
#include "dba/problem/point_order.h"

namespace dba {
namespace {

void SendShare(Communicator* comm, int rank, const RankShare& s) {
  const Traffic t = Traffic::kDistribution;
  const int32_t scalars[2] = {static_cast<int32_t>(s.problem.model), s.problem.intrinsics_size};
  comm->Send(rank, t, std::span<const int32_t>(scalars, 2));
  comm->SendVector(rank, t, s.global_camera);
  comm->SendVector(rank, t, s.global_intrinsics);
  comm->SendVector(rank, t, s.global_frame);
  comm->SendVector(rank, t, s.global_point);
  s.problem.ForEachArray([&](const auto& v) { comm->SendVector(rank, t, v); });
}

// The hook that estimates a rank's memory before its RCS's values exist
// (`role`: its sub-RCS, or the main rank's global one) and refuses when the
// growth exceeds the rank's part of what the node has available
// (lm/memory_estimate.h, as one process checks).
std::function<void(const RcsSystem&)> EstimateAndCheck(const Communicator* comm,
                                                      const LmOptions& options,
                                                      const DistributedOptions& distributed,
                                                      const Problem& problem, EstimateRole role,
                                                      MemoryEstimate* estimate,
                                                      int forming_ranks = 1,
                                                      int64_t num_observations = -1) {
  const MemoryCheckOptions check{distributed.memory_check, comm->ranks_on_node(), role, forming_ranks,
                          num_observations};
  return [=, &options, &problem](const RcsSystem& structure) {
    *estimate = EstimateAndCheckMemory(problem, structure, options, check);
  };
}

RankShare RecvShare(Communicator* comm) {
  const Traffic t = Traffic::kDistribution;
  RankShare s;
  int32_t scalars[2] = {0, 0};
  comm->Recv(0, t, std::span<int32_t>(scalars, 2));
  s.problem.model = static_cast<CameraModel>(scalars[0]);
  s.problem.intrinsics_size = scalars[1];
  s.global_camera = comm->RecvVector<int32_t>(0, t);
  s.global_intrinsics = comm->RecvVector<int32_t>(0, t);
  s.global_frame = comm->RecvVector<int32_t>(0, t);
  s.global_point = comm->RecvVector<int64_t>(0, t);
  s.problem.ForEachArray([&](auto& v) {
    v = comm->RecvVector<typename std::decay_t<decltype(v)>::value_type>(0, t);
  });
  return s;
}

template <typename T>
void Release(std::vector<T>& v) {
  std::vector<T>().swap(v);
}

// This rank's points read from the binary file, with the whole camera side
// (KeepTouchedCameras cuts it down).
RankShare ReadShare(int rank, const std::string& path, const std::vector<int32_t>& group,
                    int32_t g, const DistributedOptions& options) {
  RankShare share;
  FaultPoint(rank, "read", 1);
  share.problem = ReadBinaryPoints(path, group, g, &share.global_point);
  ApplyFixings(options.fixings, &share.problem);
  StartFovOutsideSeries(&share.problem);  // as the main rank's camera side (SolveSession::Run)
  // Walked from the positions as read, before an alignment or a resume
  // moves them: a resumed solve sums as the uninterrupted one did.
  WalkShare(&share);
  return share;
}

// What the main rank tells the others before the shares are cut: whether
// the problem's fingerprint is wanted (checkpoints) and whether the shares
// start from a checkpoint.
struct CheckpointFlags {
  int32_t fingerprint = 0;
  int32_t resume = 0;
};

// Collective, binary input: the sum of the forming ranks' observation
// fingerprints, combined with the camera side's on the main rank.
uint64_t SpreadFingerprint(Communicator* comm, const RankShare* own, int first_rank,
                           const Problem& camera_side, int64_t num_points) {
  auto part = [](const RankShare& s) {
    return ObservationsFingerprint(s.problem, s.global_point, {});
  };
  if (!comm->is_main()) {
    const uint64_t mine = part(*own);
    comm->Send(0, Traffic::kControl, std::span<const uint64_t>(&mine, 1));
    return 0;
  }
  uint64_t sum = own != nullptr ? part(*own) : 0;
  for (int r = std::max(1, first_rank); r < comm->size(); ++r) {
    uint64_t theirs = 0;
    comm->Recv(r, Traffic::kControl, std::span<uint64_t>(&theirs, 1));
    sum += theirs;
  }
  return CombineFingerprints(CameraSideFingerprint(camera_side, num_points), sum);
}

// Collective, binary input: every share's cameras and points from the main
// rank's checkpoint (the whole camera side broadcast; each rank's points
// sent to it by global id).
void ResumeShares(Communicator* comm, const Checkpoint* checkpoint, RankShare* own,
                  int first_rank) {
  const Traffic t = Traffic::kDistribution;
  auto take_points = [](const std::vector<double>& all, RankShare* s) {
    for (size_t k = 0; k < s->global_point.size(); ++k) {
      std::copy_n(all.data() + kPointSize * s->global_point[k], kPointSize, s->problem.point(k));
    }
  };
  if (!comm->is_main()) {
    comm->Broadcast(t, std::span<double>(own->problem.cameras));
    comm->SendVector(0, t, own->global_point);
    own->problem.points = comm->RecvVector<double>(0, t);
    return;
  }
  std::vector<double> cameras = checkpoint->cameras;
  comm->Broadcast(t, std::span<double>(cameras));
  if (own != nullptr) {
    own->problem.cameras = checkpoint->cameras;
    take_points(checkpoint->points, own);
  }
  for (int r = std::max(1, first_rank); r < comm->size(); ++r) {
    RankShare theirs;
    theirs.global_point = comm->RecvVector<int64_t>(r, t);
    theirs.problem.points.resize(kPointSize * theirs.global_point.size());
    take_points(checkpoint->points, &theirs);
    comm->SendVector(r, t, theirs.problem.points);
  }
}

// Point groups of a binary input: computed by every rank for the equal
// split, streamed by the main rank and broadcast for the camera-locality one.
std::vector<int32_t> BinaryPointGroups(Communicator* comm, const std::string& path,
                                       const BinaryProblemHeader& h, int groups,
                                       PartitionScheme scheme) {
  if (scheme == PartitionScheme::kEqual || groups == 1) {
    return PartitionPoints(h.num_cameras, h.num_points, h.num_observations, groups,
                           PartitionScheme::kEqual, {});
  }
  std::vector<int32_t> group(h.num_points);
  if (comm->is_main()) {
    group = PartitionPoints(
        h.num_cameras, h.num_points, h.num_observations, groups, scheme,
        [&](const VisibilityChunkFn& visit) { ForEachVisibilityChunk(path, 1 << 18, visit); });
  }
  comm->Broadcast(Traffic::kDistribution, std::span<int32_t>(group));
  return group;
}

// Collective, ranks reading a .dba: the main rank's alignment (a
// similarity, or none) moves every forming rank's points, and its cameras
// (aligned already) replace the ones the ranks read.
void AlignShares(Communicator* comm, const std::optional<Similarity>& alignment,
                 Problem* camera_side, RankShare* share) {
  int32_t aligned = comm->is_main() && alignment.has_value() ? 1 : 0;
  comm->Broadcast(Traffic::kDistribution, &aligned);
  if (aligned == 0) return;
  double packed[13] = {};
  if (comm->is_main()) {
    packed[0] = alignment->scale;
    std::copy_n(alignment->rotation.data(), 9, packed + 1);
    std::copy_n(alignment->translation.data(), 3, packed + 10);
  }
  comm->Broadcast(Traffic::kDistribution, std::span<double>(packed, 13));
  Similarity s;
  s.scale = packed[0];
  std::copy_n(packed + 1, 9, s.rotation.data());
  std::copy_n(packed + 10, 3, s.translation.data());
  if (share != nullptr) {
    std::vector<double>& points = share->problem.points;
    for (size_t k = 0; k + 2 < points.size(); k += kPointSize) {
      const Vec3 moved = s.Apply(Vec3(points[k], points[k + 1], points[k + 2]));
      std::copy_n(moved.data(), 3, &points[k]);
    }
  }
  std::vector<double>& cameras = comm->is_main() ? camera_side->cameras : share->problem.cameras;
  comm->Broadcast(Traffic::kDistribution, std::span<double>(cameras));
  if (comm->is_main() && share != nullptr) share->problem.cameras = camera_side->cameras;
}

// `extra`'s points (global ids from `first_global`; their observations'
// cameras global) appended to a share read from a .dba.
void AppendPoints(const Problem& extra, int64_t first_global, RankShare* share) {
  Problem& p = share->problem;
  for (int64_t k = 0; k < extra.num_points(); ++k) {
    if (const PointPrior* prior = extra.point_prior(k)) {
      p.point_priors.push_back(*prior);
      p.point_priors.back().point = p.num_points();
    }
    share->global_point.push_back(first_global + k);
    p.points.insert(p.points.end(), extra.point(k), extra.point(k) + kPointSize);
    for (int64_t o = extra.point_offsets[k]; o < extra.point_offsets[k + 1]; ++o) {
      p.obs_camera.push_back(extra.obs_camera[o]);
      p.obs_pixel.insert(p.obs_pixel.end(), &extra.obs_pixel[2 * o], &extra.obs_pixel[2 * o + 2]);
    }
    p.point_offsets.push_back(p.num_observations());
  }
}

// Collective, ranks reading a .dba: the control points the main rank's
// camera side holds (its only points) join the first forming rank's share
// as global points num_file_points.. Returns their count on every rank.
int64_t HandOutControlPoints(Communicator* comm, const Problem& camera_side,
                             int64_t num_file_points, int first_rank, RankShare* share) {
  const Traffic t = Traffic::kDistribution;
  int64_t count = comm->is_main() ? camera_side.num_points() : 0;
  comm->Broadcast(t, &count);
  if (count == 0) return 0;
  if (comm->is_main() && first_rank == 0) {
    AppendPoints(camera_side, num_file_points, share);
  } else if (comm->is_main()) {
    camera_side.ForEachArray([&](const auto& v) { comm->SendVector(first_rank, t, v); });
  } else if (comm->rank() == first_rank) {
    Problem extra;
    extra.ForEachArray([&](auto& v) {
      v = comm->RecvVector<typename std::decay_t<decltype(v)>::value_type>(0, t);
    });
    AppendPoints(extra, num_file_points, share);
  }
  return count;
}

}  // namespace

RcsPlacement ChooseRcsPlacement(const DistributedOptions& options, const LmOptions& lm, int ranks) {
  const LinearSolverType type = lm.linear_solver.type;
  const bool pcg = type == LinearSolverType::kAuto || type == LinearSolverType::kPcg;
  switch (options.rcs) {
    case DistributedOptions::Rcs::kGather: return RcsPlacement::kGather;
    case DistributedOptions::Rcs::kDistributed:
      if (!pcg) {
        throw std::invalid_argument(std::string("--rcs distributed solves by PCG; --linear-solver ") +
                         LinearSolverName(type) + " needs --rcs gather");
      }
      if (options.lever_arm_row) {
        throw std::invalid_argument(
            "--rcs distributed does not hold a refined lever arm (its row meets every camera's): "
            "give --rcs gather, or the lever arm held (--lever-arm X,Y,Z)");
      }
      return RcsPlacement::kDistributed;
    case DistributedOptions::Rcs::kAuto: break;
  }
  return ranks > 1 && pcg && !options.lever_arm_row ? RcsPlacement::kDistributed
                                                    : RcsPlacement::kGather;
}

namespace {

// Whether the main rank forms a sub-RCS: decided there, told to every rank
// (ranks may have been given other options).
bool MainForms(Communicator* comm, const DistributedOptions& d) {
  int32_t forms = comm->size() == 1 || d.main_role == DistributedOptions::MainRole::kForms ||
                  (d.main_role == DistributedOptions::MainRole::kAuto &&
                   comm->size() <= DistributedOptions::kMainFormsUpTo);
  comm->Broadcast(Traffic::kControl, &forms);
  return forms != 0;
}

RcsPlacement Placement(Communicator* comm, const DistributedOptions& d, const LmOptions& options) {
  int32_t placement = 0;
  if (comm->is_main()) placement = static_cast<int32_t>(ChooseRcsPlacement(d, options, comm->size()));
  comm->Broadcast(Traffic::kControl, &placement);
  return static_cast<RcsPlacement>(placement);
}

}  // namespace

DistributedPointSide::DistributedPointSide(Communicator* comm, const LmOptions& options,
                                           const DistributedOptions& distributed,
                                           const std::string& binary_input, Problem* problem,
                                           const DistributedCheckpoints& checkpoints,
                                           const std::optional<Similarity>& alignment,
                                           const std::optional<std::vector<int64_t>>& walk)
    : comm_(comm), distributed_(distributed), problem_(problem) {
  summary_.ranks = comm->size();
  summary_.partition = distributed.partition;
  summary_.main_forms = MainForms(comm, distributed);
  CheckpointFlags flags{checkpoints.writer != nullptr || checkpoints.resume != nullptr,
                        checkpoints.resume != nullptr};
  comm->Broadcast(Traffic::kControl, &flags);
  summary_.rcs = Placement(comm, distributed, options);
  // The linear solve's options, the same on every rank (distributed PCG).
  linear_ = LinearSolverOptionsFor(options, 0);
  groups_ = comm->size() - (summary_.main_forms ? 0 : 1);
  mine_ = summary_.main_forms ? &own_ : nullptr;
  Timer distribution;
  Distribute(binary_input, checkpoints, alignment, walk);
  summary_.distribution_seconds = distribution.Seconds();
}

DistributedPointSide::~DistributedPointSide() = default;

// Partition and hand out the shares, each walked here (or let the ranks
// read theirs and walk them).
void DistributedPointSide::Distribute(const std::string& binary_input,
                                      const DistributedCheckpoints& checkpoints,
                                      const std::optional<Similarity>& alignment,
                                      const std::optional<std::vector<int64_t>>& walk) {
  const int first_rank = summary_.main_forms ? 0 : 1;
  if (!binary_input.empty()) {
    ReadShares(binary_input, checkpoints, alignment);
    return;
  }
  const std::vector<int32_t> group = PartitionPoints(*problem_, groups_, distributed_.partition);
  const std::vector<int64_t> place = walk ? InversePermutation(*walk) : std::vector<int64_t>();
  for (int g = 0; g < groups_; ++g) {
    const int rank = g + first_rank;
    RankShare share = ExtractShare(*problem_, group, g);
    if (!walk || !walk->empty()) WalkShare(&share, place);
    if (rank == 0) {
      own_ = std::move(share);
    } else {
      SendShare(comm_, rank, share);
    }
  }
  // The observations now live on the ranks.
  num_observations_ = problem_->num_observations();
  num_points_ = problem_->num_points();
  Release(problem_->points);
  Release(problem_->point_offsets);
  Release(problem_->obs_camera);
  Release(problem_->obs_pixel);
}

// Every forming rank reads its points of the .dba; the main rank's camera
// side (as the caller prepared it) is the ranks' unknowns. Moved by the
// alignment, joined by the control points, checked against a checkpoint's
// fingerprint and started from it.
void DistributedPointSide::ReadShares(const std::string& binary_input,
                                      const DistributedCheckpoints& checkpoints,
                                      const std::optional<Similarity>& alignment) {
  const int first_rank = summary_.main_forms ? 0 : 1;
  const BinaryProblemHeader header = ReadBinaryProblemHeader(binary_input);
  const std::vector<int32_t> group =
      BinaryPointGroups(comm_, binary_input, header, groups_, distributed_.partition);
  if (mine_ != nullptr) own_ = ReadShare(0, binary_input, group, 0, distributed_);
  AlignShares(comm_, alignment, problem_, mine_);
  const int64_t control = HandOutControlPoints(comm_, *problem_, header.num_points, first_rank, mine_);
  num_points_ = header.num_points + control;
  num_observations_ = header.num_observations + problem_->num_observations();
  // The main rank keeps the camera side and, collected at the end, the
  // points; not the observations.
  Release(problem_->points);
  Release(problem_->point_offsets);
  Release(problem_->obs_camera);
  Release(problem_->obs_pixel);
  Release(problem_->point_priors);
  const bool wanted = checkpoints.writer != nullptr || checkpoints.resume != nullptr;
  if (wanted) {
    const uint64_t fingerprint = SpreadFingerprint(comm_, mine_, first_rank, *problem_, num_points_);
    if (checkpoints.writer != nullptr) checkpoints.writer->set_fingerprint(fingerprint);
    if (checkpoints.resume != nullptr) {
      CheckCheckpointFits(*checkpoints.resume, checkpoints.resume_path, fingerprint,
                          problem_->cameras.size(), kPointSize * num_points_);
    }
  }
  if (checkpoints.resume != nullptr) {
    ResumeShares(comm_, checkpoints.resume, mine_, first_rank);
    problem_->cameras = std::exchange(checkpoints.resume->cameras, {});
    checkpoints.resume->points = {};  // handed out to the ranks
  }
  if (mine_ != nullptr) KeepTouchedCameras(mine_);
}

// The workers: the main rank's own share's (if it forms) and the global RCS
// over every rank's; made again after each rejection round.
void DistributedPointSide::MakeWorkers(const LmOptions& o, bool lever_arm) {
  // The lever arm's row meets every camera row: gathered only (the
  // placement's choice, ChooseRcsPlacement).
  if (lever_arm && summary_.rcs == RcsPlacement::kDistributed) {
    throw std::logic_error("a refined lever arm in an RCS spread over ranks");
  }
  workers_.reset();
  own_workers_.reset();
  if (mine_ != nullptr) {
    own_workers_ = std::make_unique<LocalPointWorkers>(
        &own_.problem, o.damping, o.num_threads, o.loss,
        EstimateAndCheck(comm_, o, distributed_, own_.problem, EstimateRole::kForms,
                         &own_estimate_),
        summary_.rcs == RcsPlacement::kDistributed);
  }
  workers_ = std::make_unique<MpiPointWorkers>(
      comm_, UnknownLayout(*problem_, lever_arm), mine_, own_workers_.get(),
      EstimateAndCheck(comm_, o, distributed_, *problem_, EstimateRole::kSolves,
                       &summary_.memory_estimate, groups_, num_observations_),
      summary_.rcs, linear_, o.damping, problem_->cameras.data());
}

void DistributedPointSide::CurrentWorkers(const LmOptions& options, const CameraPriors& priors) {
  if (stale_) workers_->Rebuild(keep_loss_);  // the ranks make theirs again
  if (workers_ == nullptr || stale_) MakeWorkers(options, priors.refine_lever_arm && !priors.empty());
  stale_ = false;
}

void DistributedPointSide::AtOptimum(const LmOptions& options, const CameraPriors& priors,
                                     const std::function<void(const RcsSystem&)>& look) {
  CurrentWorkers(options, priors);
  FormAtCurrentParameters(*problem_, workers_.get(), &priors, look);
}

BundleAdjustSummary DistributedPointSide::Solve(
    const LmOptions& options, const CameraPriors& priors, const IterationHook& on_iteration,
    const std::function<void(const RcsSystem&)>&) {
  BundleAdjustSummary s;
  Timer symbolic;
  CurrentWorkers(options, priors);
  s.symbolic_seconds = symbolic.Seconds();
  s.rcs = workers_->footprint();
  TrafficStats before = comm_->stats();
  auto log = [&](const IterationSummary& it) {
    TrafficStats delta;
    for (int t = 0; t < kNumTraffic; ++t) {
      delta.bytes[t] = comm_->stats().bytes[t] - before.bytes[t];
      delta.seconds[t] = comm_->stats().seconds[t] - before.seconds[t];
    }
    before = comm_->stats();
    summary_.per_iteration.push_back(delta);
    if (on_iteration) on_iteration(it);
  };
  // The other ranks on this node busy-wait in MPI while the main rank
  // factorizes: BLAS threads would compete with them (sparse_cholesky.h).
  LmOptions o = options;
  if (comm_->ranks_on_node() > 1) o.linear_solver.threaded_blas = false;
  PriorSolve solve = SolveWithPriors(o, num_observations_, *problem_, &problem_->cameras,
                                     workers_.get(), &priors, log);
  s.lm = std::move(solve.lm);
  s.lever_arm = solve.lever_arm;
  return s;
}

RejectionRound DistributedPointSide::DropOutliers(const RejectionCriteria& criteria,
                                                  int num_threads, bool keep_loss,
                                                  PoseObservations* poses) {
  *poses = PoseObservations();
  poses->before.assign(problem_->num_frames(), 0);
  poses->after.assign(problem_->num_frames(), 0);
  const RejectionRound round =
      workers_->DropOutliers(criteria, num_threads, &own_rejection_, poses);
  num_observations_ = round.observations_left;
  stale_ = true;
  keep_loss_ = keep_loss;
  return round;
}

void DistributedPointSide::AllPoints(std::vector<double>* points) {
  points_.resize(kPointSize * num_points_);
  workers_->CollectPoints(&points_);
  *points = points_;
}

KeptObservations DistributedPointSide::Kept() {
  return MergeLeft(workers_->CollectLeft(&own_rejection_), num_points_);
}

void DistributedPointSide::Finish(bool collect_points, SolveOnRanksSummary* summary) {
  if (collect_points) problem_->points.resize(kPointSize * num_points_);
  // Distributed, the main rank's estimate is its own share's (it holds no
  // global RCS).
  if (summary_.rcs == RcsPlacement::kDistributed) summary_.memory_estimate = own_estimate_;
  summary_.rank_reports = workers_->Finish(collect_points ? &problem_->points : nullptr,
                                           summary_.memory_estimate.total(),
                                           &summary_.rank_per_iteration);
  summary_.traffic = comm_->stats();
  BundleAdjustSummary ba = std::move(summary->ba);
  *summary = std::move(summary_);
  summary->ba = std::move(ba);
}

void ServePoints(Communicator* comm, const LmOptions& options, const DistributedOptions& distributed,
                 const std::string& binary_input, const DistributedCheckpoints&) {
  const bool main_forms = MainForms(comm, distributed);
  CheckpointFlags flags;
  comm->Broadcast(Traffic::kControl, &flags);
  const RcsPlacement placement = Placement(comm, distributed, options);
  const LinearSolverOptions linear = LinearSolverOptionsFor(options, 0);
  const int first_rank = main_forms ? 0 : 1;
  RankShare share;
  if (!binary_input.empty()) {
    const BinaryProblemHeader header = ReadBinaryProblemHeader(binary_input);
    const std::vector<int32_t> group = BinaryPointGroups(comm, binary_input, header,
                                                         comm->size() - first_rank,
                                                         distributed.partition);
    share = ReadShare(comm->rank(), binary_input, group, comm->rank() - first_rank, distributed);
    AlignShares(comm, std::nullopt, nullptr, &share);
    HandOutControlPoints(comm, Problem(), header.num_points, first_rank, &share);
    if (flags.fingerprint) SpreadFingerprint(comm, &share, first_rank, {}, 0);
    if (flags.resume) ResumeShares(comm, nullptr, &share, first_rank);
    KeepTouchedCameras(&share);
  } else {
    share = RecvShare(comm);  // walked by the main rank
  }
  // Served until the end; again with new workers after each rejection
  // round that asks for another solve.
  ShareRejection rejection;
  RobustLoss loss = options.loss;
  for (;;) {
    MemoryEstimate estimate;
    LocalPointWorkers workers(&share.problem, options.damping, options.num_threads, loss,
                              EstimateAndCheck(comm, options, distributed, share.problem,
                                               EstimateRole::kForms, &estimate),
                              placement == RcsPlacement::kDistributed);
    const RankLoopEnd end = RunPointRank(comm, &share, &workers, estimate.total(), &rejection,
                                         placement, linear, options.damping);
    if (!end.rebuild) return;
    if (!end.keep_loss) loss = RobustLoss();
  }
}

}  // namespace dba
