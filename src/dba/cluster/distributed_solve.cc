// Distributed bundle adjustment; see distributed_solve.h.
#include "dba/cluster/distributed_solve.h"

#include "dba/common/memory.h"

#include "dba/common/timer.h"
#include <stdexcept>
#include <string>
#include <utility>
#include "dba/io/binary_problem.h"

namespace dba {
namespace {

void SendShare(Communicator* comm, int rank, const RankShare& s) {
  const Traffic t = Traffic::kDistribution;
  const int32_t scalars[2] = {static_cast<int32_t>(s.problem.model), s.problem.intrinsics_size};
  comm->Send(rank, t, std::span<const int32_t>(scalars, 2));
  comm->SendVector(rank, t, s.global_camera);
  comm->SendVector(rank, t, s.global_intrinsics);
  comm->SendVector(rank, t, s.global_point);
  s.problem.ForEachArray([&](const auto& v) { comm->SendVector(rank, t, v); });
}

// The hook that estimates a rank's memory before its RCS's values exist
// (`role`: its sub-RCS, or the main rank's global one) and refuses when the
// growth exceeds the rank's part of what the node has available.
std::function<void(const RcsSystem&)> EstimateAndCheck(const Communicator* comm,
                                                      const LmOptions& options,
                                                      const DistributedOptions& distributed,
                                                      const Problem& problem, EstimateRole role,
                                                      MemoryEstimate* estimate,
                                                      int forming_ranks = 1,
                                                      int64_t num_observations = -1) {
  return [=, &options, &problem](const RcsSystem& structure) {
    *estimate = EstimateSolveMemory(problem, structure, options, CurrentResidentBytes(),
                                    PeakResidentBytes(), role, num_observations);
    // The main rank's one message buffer (its own packed sub-RCS, then each
    // rank's in turn): about a forming rank's share of the global RCS.
    if (role == EstimateRole::kSolves) {
      estimate->messages = structure.S.ValueBytes() / std::max(1, forming_ranks);
    }
    if (!distributed.memory_check) return;
    const int64_t available = AvailableMemoryBytes();
    CheckMemoryFits(*estimate, available / std::max(1, comm->ranks_on_node()));
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
  MaybeInjectFault(rank, "read", 1);
  share.problem = ReadBinaryPoints(path, group, g, &share.global_point);
  ApplyFixings(options.fixings, &share.problem);
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
      return RcsPlacement::kDistributed;
    case DistributedOptions::Rcs::kAuto: break;
  }
  return ranks > 1 && pcg ? RcsPlacement::kDistributed : RcsPlacement::kGather;
}

DistributedSummary DistributedBundleAdjust(
    Communicator* comm, const LmOptions& options, const DistributedOptions& distributed,
    const std::string& binary_input, bool collect_points, Problem* problem,
    const DistributedHooks& hooks) {
  const DistributedCheckpoints& checkpoints = hooks.checkpoints;
  DistributedSummary summary;
  summary.ranks = comm->size();
  summary.partition = distributed.partition;
  summary.main_forms =
      comm->size() == 1 ||
      distributed.main_role == DistributedOptions::MainRole::kForms ||
      (distributed.main_role == DistributedOptions::MainRole::kAuto &&
       comm->size() <= DistributedOptions::kMainFormsUpTo);
  // Everyone learns the decision (ranks may have been given other options).
  int32_t main_forms = summary.main_forms ? 1 : 0;
  comm->Broadcast(Traffic::kControl, &main_forms);
  summary.main_forms = main_forms != 0;
  CheckpointFlags flags{checkpoints.writer != nullptr || checkpoints.resume != nullptr,
                        checkpoints.resume != nullptr};
  comm->Broadcast(Traffic::kControl, &flags);
  int32_t placement = 0;
  if (comm->is_main()) {
    placement = static_cast<int32_t>(ChooseRcsPlacement(distributed, options, comm->size()));
  }
  comm->Broadcast(Traffic::kControl, &placement);
  summary.rcs = static_cast<RcsPlacement>(placement);
  // The linear solve's options, the same on every rank (distributed PCG).
  const LinearSolverOptions linear = LinearSolverOptionsFor(options, 0);

  const bool from_file = !binary_input.empty();
  BinaryProblemHeader header;
  if (from_file) header = ReadBinaryProblemHeader(binary_input);
  const int first_rank = summary.main_forms ? 0 : 1;
  const int groups = comm->size() - first_rank;

  if (!comm->is_main()) {
    RankShare share;
    if (from_file) {
      const std::vector<int32_t> group =
          BinaryPointGroups(comm, binary_input, header, groups, distributed.partition);
      share = ReadShare(comm->rank(), binary_input, group, comm->rank() - first_rank, distributed);
      if (flags.fingerprint) SpreadFingerprint(comm, &share, first_rank, {}, 0);
      if (flags.resume) ResumeShares(comm, nullptr, &share, first_rank);
      KeepTouchedCameras(&share);
    } else {
      share = RecvShare(comm);
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
                                summary.rcs == RcsPlacement::kDistributed);
      const RankLoopEnd end = RunPointRank(comm, &share, &workers, estimate.total(), &rejection,
                                           summary.rcs, linear, options.damping);
      if (!end.rebuild) return summary;
      if (!end.keep_loss) loss = RobustLoss();
    }
  }

  // Main rank: partition and hand out the shares.
  Timer distribution;
  RankShare own;
  RankShare* mine = summary.main_forms ? &own : nullptr;
  int64_t num_observations = 0, num_points = 0;
  if (from_file) {
    const std::vector<int32_t> group =
        BinaryPointGroups(comm, binary_input, header, groups, distributed.partition);
    if (summary.main_forms) own = ReadShare(0, binary_input, group, 0, distributed);
    // The main rank keeps the camera side (model, image groups, fixed flags:
    // its unknowns must be the ranks') and point coordinates, not
    // observations.
    *problem = Problem(ReadBinaryCameraSide(binary_input));
    ApplyFixings(distributed.fixings, problem);
    if (flags.fingerprint) {
      const uint64_t fingerprint =
          SpreadFingerprint(comm, mine, first_rank, *problem, header.num_points);
      if (checkpoints.writer != nullptr) checkpoints.writer->set_fingerprint(fingerprint);
      if (checkpoints.resume != nullptr) {
        CheckCheckpointFits(*checkpoints.resume, checkpoints.resume_path, fingerprint,
                            problem->cameras.size(), kPointSize * header.num_points);
      }
    }
    if (flags.resume) {
      ResumeShares(comm, checkpoints.resume, mine, first_rank);
      problem->cameras = std::exchange(checkpoints.resume->cameras, {});
      checkpoints.resume->points = {};  // handed out to the ranks
    }
    if (mine != nullptr) KeepTouchedCameras(mine);
    if (collect_points) problem->points.resize(kPointSize * header.num_points);
    num_observations = header.num_observations;
    num_points = header.num_points;
  } else {
    const std::vector<int32_t> group =
        PartitionPoints(*problem, groups, distributed.partition);
    for (int g = 0; g < groups; ++g) {
      const int rank = g + first_rank;
      if (rank == 0) {
        own = ExtractShare(*problem, group, g);
      } else {
        SendShare(comm, rank, ExtractShare(*problem, group, g));
      }
    }
    // The observations now live on the ranks.
    num_observations = problem->num_observations();
    num_points = problem->num_points();
    if (!collect_points) Release(problem->points);
    Release(problem->point_offsets);
    Release(problem->obs_camera);
    Release(problem->obs_pixel);
  }
  summary.distribution_seconds = distribution.Seconds();

  // The workers: the main rank's own share's (if it forms) and the global
  // RCS over every rank's; made again after each rejection round.
  Timer symbolic;
  std::unique_ptr<LocalPointWorkers> own_workers;
  std::unique_ptr<MpiPointWorkers> workers;
  MemoryEstimate own_estimate;
  auto make_workers = [&](const LmOptions& o) {
    workers.reset();
    own_workers.reset();
    if (mine != nullptr) {
      own_workers = std::make_unique<LocalPointWorkers>(
          &own.problem, o.damping, o.num_threads, o.loss,
          EstimateAndCheck(comm, o, distributed, own.problem, EstimateRole::kForms,
                           &own_estimate),
          summary.rcs == RcsPlacement::kDistributed);
    }
    workers = std::make_unique<MpiPointWorkers>(
        comm, UnknownLayout(*problem), mine, own_workers.get(),
        EstimateAndCheck(comm, o, distributed, *problem, EstimateRole::kSolves,
                         &summary.memory_estimate, groups, num_observations),
        summary.rcs, linear, o.damping, problem->cameras.data());
  };
  make_workers(options);
  summary.ba.symbolic_seconds = symbolic.Seconds();
  summary.ba.rcs = workers->footprint();

  TrafficStats before = comm->stats();
  auto log = [&](const IterationSummary& it) {
    TrafficStats delta;
    for (int t = 0; t < kNumTraffic; ++t) {
      delta.bytes[t] = comm->stats().bytes[t] - before.bytes[t];
      delta.seconds[t] = comm->stats().seconds[t] - before.seconds[t];
    }
    before = comm->stats();
    summary.per_iteration.push_back(delta);
    if (hooks.on_iteration) hooks.on_iteration(it);
    if (checkpoints.writer != nullptr && checkpoints.writer->Due(it.step_accepted, it.ends_solve)) {
      // The main rank's points, if it keeps them, are collected in place.
      std::vector<double> scratch;
      std::vector<double>& points = collect_points ? problem->points : scratch;
      points.resize(kPointSize * num_points);
      workers->CollectPoints(&points);
      Checkpoint state;
      state.iterations = it.iteration;
      state.lambda = it.next_lambda;
      state.cost = it.candidate_cost;
      state.ended = it.ends_solve ? static_cast<int32_t>(it.termination) : -1;
      checkpoints.writer->Write(state, problem->cameras, points);
    }
  };
  // The other ranks on this node busy-wait in MPI while the main rank
  // factorizes: BLAS threads would compete with them (sparse_cholesky.h).
  LmOptions main_options = options;
  if (comm->ranks_on_node() > 1) main_options.linear_solver.threaded_blas = false;
  // With camera priors the LM loop sees the workers through PriorWorkers.
  const auto solve = [&](const LmOptions& lm) {
    if (distributed.priors.empty()) {
      return SolveLevenbergMarquardt(lm, num_observations, &problem->cameras, workers.get(), log);
    }
    PriorWorkers with_priors(workers.get(), &problem->cameras, problem->camera_size(),
                             distributed.priors);
    return SolveLevenbergMarquardt(lm, num_observations, &problem->cameras, &with_priors, log);
  };
  summary.ba.lm = solve(main_options);
  if (distributed.reject_outliers) {
    ShareRejection own_rejection;
    LmOptions resolve = main_options;
    if (!distributed.reject_keep_loss) resolve.loss = RobustLoss();
    summary.rejection = RunRejectionRounds(
        [&] {
          const RejectionRound round =
              workers->DropOutliers(distributed.rejection, options.num_threads, &own_rejection);
          num_observations = round.observations_left;
          return round;
        },
        [&] {
          Timer again;
          workers->Rebuild(distributed.reject_keep_loss);
          make_workers(resolve);
          BundleAdjustSummary next;
          next.symbolic_seconds = again.Seconds();
          next.rcs = workers->footprint();
          next.lm = solve(resolve);
          AppendSolve(next, &summary.ba);
        },
        [&](int r, const RejectionRound& round) {
          if (hooks.on_rejection_round) hooks.on_rejection_round(r, round);
        });
    summary.kept = MergeLeft(workers->CollectLeft(&own_rejection), num_points);
  }
  // Distributed, the main rank's estimate is its own share's (it holds no
  // global RCS).
  if (summary.rcs == RcsPlacement::kDistributed) summary.memory_estimate = own_estimate;
  summary.rank_reports = workers->Finish(collect_points ? &problem->points : nullptr,
                                        summary.memory_estimate.total(),
                                        &summary.rank_per_iteration);
  summary.traffic = comm->stats();
  return summary;
}

}  // namespace dba
