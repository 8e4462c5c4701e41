// The distributed iteration protocol; see mpi_point_workers.h.
#include "dba/cluster/mpi_point_workers.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "dba/common/memory.h"
#include "dba/rcs/aggregation_order.h"
#include "dba/rcs/rigid_motion_basis.h"

namespace dba {
namespace {

enum class Op : int32_t {
  kForm = 1, kStep = 2, kFinish = 3, kEnd = 4, kCollect = 5, kReject = 6, kRebuild = 7, kLeft = 8,
  kSolve = 9
};

struct Command {
  Op op;
  int32_t accept;  // FINISH: accept; END: send points; REBUILD: keep the loss;
                   // SOLVE: drop the damping floor first; FORM: pose terms follow
  double lambda;   // FORM, STEP: λ; REJECT: the largest error kept (px)
  double value = 0.0;  // REJECT: the smallest triangulation angle kept (deg)
};

void BroadcastCommand(Communicator* comm, Command c) {
  comm->Broadcast(Traffic::kControl, &c);
}

// The slices of the global δc that belong to a share's rows, in its order.
std::vector<double> LocalDelta(const std::vector<double>& global, const UnknownLayout& layout,
                               const std::vector<int32_t>& rows) {
  std::vector<double> local;
  for (int32_t r : rows) {
    const double* d = global.data() + layout.row_offset(r);
    local.insert(local.end(), d, d + layout.block_size(r));
  }
  return local;
}

constexpr int kPackedEvaluation = 11;  // values of Pack(StepEvaluation)

std::vector<double> Pack(const StepEvaluation& e) {
  const PositionSpread& p = e.point_spread;
  return {e.model_cost, e.candidate_cost, e.point_step_squared_norm,
          e.candidate_residuals.squared, e.candidate_residuals.inlier_squared,
          e.candidate_residuals.inliers, p.count, p.mean[0], p.mean[1], p.mean[2], p.m2};
}

constexpr int kPackedRound = 5;  // values of Pack(RejectionRound)

std::vector<double> Pack(const RejectionRound& r) {
  return {static_cast<double>(r.observations_dropped), static_cast<double>(r.points_dropped),
          static_cast<double>(r.points_small_angle), static_cast<double>(r.observations_left),
          static_cast<double>(r.points_left)};
}

void SendLeft(Communicator* comm, const ShareLeft& left) {
  comm->SendVector(0, Traffic::kResult, left.point);
  comm->SendVector(0, Traffic::kResult, left.count);
  comm->SendVector(0, Traffic::kResult, left.point_kept);
  comm->SendVector(0, Traffic::kResult, left.observation_kept);
}

ShareLeft RecvLeft(Communicator* comm, int rank) {
  ShareLeft left;
  left.point = comm->RecvVector<int64_t>(rank, Traffic::kResult);
  left.count = comm->RecvVector<int64_t>(rank, Traffic::kResult);
  left.point_kept = comm->RecvVector<uint8_t>(rank, Traffic::kResult);
  left.observation_kept = comm->RecvVector<uint8_t>(rank, Traffic::kResult);
  return left;
}

// Collective, distributed RCS: the global block sizes from the main rank,
// this rank's sub-RCS rows in global numbering (the main rank maps every
// rank's row entities), then the owners' parts (cluster/distributed_rcs.h).
std::unique_ptr<DistributedRcs> BuildDistributedRcs(Communicator* comm, const UnknownLayout* global,
                                                    const RankShare* share,
                                                    const LocalPointWorkers* workers,
                                                    const LinearSolverOptions& linear,
                                                    const double* cameras) {
  const Traffic t = Traffic::kDistribution;
  std::vector<int32_t> sizes;
  if (comm->is_main()) sizes = global->block_sizes();
  int64_t n = static_cast<int64_t>(sizes.size());
  comm->Broadcast(t, &n);
  sizes.resize(n);
  comm->Broadcast(t, std::span<int32_t>(sizes));
  std::vector<int64_t> entities;
  if (workers != nullptr) {
    entities = workers->system().layout.RowEntities(share->CameraRowIds(), share->global_intrinsics);
  }
  std::vector<int32_t> rows;
  if (comm->is_main()) {
    rows = global->RowsOfEntities(entities);
    for (int r = 1; r < comm->size(); ++r) {
      comm->SendVector(r, t, global->RowsOfEntities(comm->RecvVector<int64_t>(r, t)));
    }
  } else {
    comm->SendVector(0, t, entities);
    rows = comm->RecvVector<int32_t>(0, t);
  }
  // The two-level preconditioner's bases, at the current cameras.
  std::vector<CoarseRowBasis> bases;
  if (comm->is_main() && linear.preconditioner == PreconditionerType::kTwoLevel &&
      linear.coarse_basis != CoarseBasis::kParameters) {
    bases = RigidMotionBases(*global, cameras, linear.coarse_basis == CoarseBasis::kSimilarity);
  }
  // ... and the order its aggregation meets the rows in (the cameras' places).
  LinearSolverOptions options = linear;
  options.aggregation_order.clear();
  if (comm->is_main() && linear.preconditioner == PreconditionerType::kTwoLevel) {
    options.aggregation_order = AggregationOrder(*global, cameras);
  }
  return std::make_unique<DistributedRcs>(comm, std::move(sizes),
                                          workers != nullptr ? &workers->system().S : nullptr,
                                          std::move(rows), options, bases);
}

// Collective: the owners' parts of the RCS summed into one footprint (own
// rows only; the halo's zero diagonal blocks are scratch).
RcsFootprint OwnedFootprint(Communicator* comm, const DistributedRcs& d) {
  const BsmcMatrix& S = d.own_matrix();
  const int32_t n = d.num_own_rows();
  const int64_t blocks = n > 0 ? S.row_end(n - 1) : 0;
  int64_t csr_entries = 0;  // both triangles
  for (int32_t i = 0; i < n; ++i) {
    for (int64_t b = S.row_begin(i); b < S.row_end(i); ++b) {
      const int64_t e = int64_t{S.block_size(i)} * S.block_size(S.block_col(b));
      csr_entries += S.block_col(b) == i ? e : 2 * e;
    }
  }
  const int64_t values = n > 0 ? S.value_offset(blocks) : 0;
  int64_t f[6] = {n, blocks, S.scalar_offset(n),
                  (n + 1) * 8 + blocks * 12 /* row starts, columns, value offsets */,
                  values * 8, csr_entries * 12 + (S.scalar_offset(n) + 1) * 8};
  comm->AllreduceSum(Traffic::kDistribution, f);
  RcsFootprint fp;
  fp.block_rows = f[0];
  fp.blocks = f[1];
  fp.camera_unknowns = f[2];
  fp.bsmc_structure_bytes = f[3];
  fp.bsmc_value_bytes = f[4];
  fp.csr_bytes = f[5];
  return fp;
}

}  // namespace

const char* RcsPlacementName(RcsPlacement placement) {
  return placement == RcsPlacement::kDistributed ? "distributed" : "gather";
}

RankReport MakeRankReport(int rank, const RankShare& share,
                          const LocalPointWorkers* workers, const Communicator& comm,
                          int64_t memory_estimate_bytes, const DistributedRcs* distributed) {
  RankReport r;
  r.memory_estimate_bytes = memory_estimate_bytes;
  r.rank = rank;
  r.points = share.problem.num_points();
  r.observations = share.problem.num_observations();
  r.cameras = static_cast<int64_t>(share.global_camera.size());
  if (workers != nullptr) {
    const BsmcMatrix& S = workers->system().S;
    r.sub_rcs_blocks = S.num_blocks();
    r.sub_rcs_bytes = S.StructureBytes() + S.ValueBytes();
  }
  if (distributed != nullptr) {
    const BsmcMatrix& S = distributed->own_matrix();
    const int32_t n = distributed->num_own_rows();
    r.owned_rows = n;
    r.owned_blocks = n > 0 ? S.row_end(n - 1) : 0;
    r.owned_bytes = distributed->MemoryBytes();
    r.halo_rows = S.num_block_rows() - n;
  }
  r.peak_memory_bytes = PeakResidentBytes();
  r.traffic_bytes = comm.stats().total_bytes();
  r.traffic = comm.stats();
  return r;
}

// The linear solve of a distributed RCS, on the main rank: every rank
// joins it (SOLVE); δc comes back whole.
class MpiPointWorkers::DistributedSolver : public DampedRcsSolver {
 public:
  explicit DistributedSolver(MpiPointWorkers* w) : w_(w) {}
  LinearSolveSummary Solve(double lambda, const DampingBounds& bounds, RcsSystem* system,
                           double* delta_c) override {
    (void)bounds;  // every rank damps with its own (the same options)
    (void)system;
    // SOLVE's flag: the other ranks' products turn to double first.
    BroadcastCommand(w_->comm_, {Op::kSolve, drop_floor_ ? 1 : 0, lambda});
    drop_floor_ = false;
    const LinearSolveSummary s = w_->distributed_->Solve(lambda, w_->bounds_);
    std::vector<double> all;
    w_->distributed_->SpreadStep(w_->own_ != nullptr ? &w_->own_delta_ : nullptr, &all);
    std::copy(all.begin(), all.end(), delta_c);
    return s;
  }
  // The main rank's, beyond its rows of the RCS.
  int64_t MemoryBytes() const override {
    const BsmcMatrix& S = w_->distributed_->own_matrix();
    return w_->distributed_->MemoryBytes() - S.ValueBytes() - S.StructureBytes();
  }
  double min_lambda() const override { return w_->distributed_->min_lambda(); }
  // The main rank's now, the others' at the next SOLVE.
  bool DropDampingFloor() override {
    drop_floor_ = w_->distributed_->DropDampingFloor();
    return drop_floor_;
  }

 private:
  MpiPointWorkers* w_;
  bool drop_floor_ = false;  // to tell the other ranks at the next SOLVE
};

MpiPointWorkers::~MpiPointWorkers() = default;

std::unique_ptr<DampedRcsSolver> MpiPointWorkers::MakeDampedRcsSolver(
    RcsSystem& system, const LinearSolverOptions& options, RcsSolverChoice* choice) {
  if (placement_ == RcsPlacement::kGather) {
    return PointWorkers::MakeDampedRcsSolver(system, options, choice);
  }
  if (choice != nullptr) {
    *choice = RcsSolverChoice();
    choice->type = LinearSolverType::kPcg;
    choice->reason = "the RCS is spread over " + std::to_string(comm_->size()) +
                     " ranks: PCG across them, " + PreconditionerName(options.preconditioner) +
                     " preconditioner";
    choice->pcg_bytes = distributed_->MemoryBytes();
  }
  return std::make_unique<DistributedSolver>(this);
}

MpiPointWorkers::MpiPointWorkers(Communicator* comm, UnknownLayout layout,
                                 RankShare* own_share, LocalPointWorkers* own,
                                 const std::function<void(const RcsSystem&)>& before_values,
                                 RcsPlacement placement, const LinearSolverOptions& linear,
                                 const DampingBounds& bounds, const double* cameras)
    : comm_(comm), own_share_(own_share), own_(own), placement_(placement), bounds_(bounds) {
  if (placement == RcsPlacement::kDistributed) {
    distributed_ = BuildDistributedRcs(comm, &layout, own_share, own, linear, cameras);
    footprint_ = OwnedFootprint(comm, *distributed_);
    if (own != nullptr) {
      maps_.resize(1);
      maps_[0].global_row = layout.RowsOfEntities(own->system().layout.RowEntities(
          own_share->CameraRowIds(), own_share->global_intrinsics));
    }
    global_.layout = std::move(layout);
    return;
  }
  // Every rank's sub-RCS pattern in global numbering; the global pattern is
  // their union (plus every diagonal block).
  std::vector<std::vector<uint64_t>> local_patterns(comm->size());
  std::vector<std::vector<int32_t>> rows(comm->size());
  if (own != nullptr) {
    local_patterns[0] = BlockPattern(own->system().S);
    rows[0] = layout.RowsOfEntities(own->system().layout.RowEntities(
        own_share->CameraRowIds(), own_share->global_intrinsics));
  }
  for (int r = 1; r < comm->size(); ++r) {
    local_patterns[r] = comm->RecvVector<uint64_t>(r, Traffic::kDistribution);
    rows[r] = layout.RowsOfEntities(comm->RecvVector<int64_t>(r, Traffic::kDistribution));
  }
  GlobalRcs global =
      BuildGlobalRcs(std::move(layout), local_patterns, std::move(rows), before_values);
  global_ = std::move(global.system);
  maps_ = std::move(global.maps);
  footprint_ = RcsFootprint::Of(global_.S);
}

RcsSystem& MpiPointWorkers::FormRcs(double lambda) {
  // FORM's flag: the owners add pose terms from the main rank.
  const bool with_pose_terms = !pose_terms_.empty();
  BroadcastCommand(comm_, {Op::kForm, with_pose_terms ? 1 : 0, lambda});
  ++formations_;
  if (distributed_ != nullptr) {
    const RcsSystem* sub = nullptr;
    if (own_ != nullptr) {
      FaultPoint(0, "form", formations_);
      sub = &own_->FormRcs(lambda);
    }
    std::vector<PoseRowTerm> terms;
    for (PoseRowTerm& t : pose_terms_) {
      t.row = global_.layout.camera_row(t.image);
      if (t.row >= 0) terms.push_back(t);  // a fixed camera's term has no row
    }
    pose_terms_.clear();
    const RcsTotals totals = distributed_->Reduce(sub, with_pose_terms, terms);
    if (own_ != nullptr) own_->ReleaseRcsValues();  // summed into the owners' rows
    global_.cost = totals.cost;
    global_.residuals = totals.residuals;
    global_.camera_side_gradient.assign(1, totals.max_abs_gradient);
    global_.max_abs_point_gradient = totals.max_abs_gradient;
    return global_;
  }
  ClearRcs(&global_);
  if (own_ != nullptr) {
    FaultPoint(0, "form", formations_);
    PackSubRcs(own_->FormRcs(lambda), &message_);
    AggregateSubRcs(maps_[0], message_, &global_);
  }
  for (int r = 1; r < comm_->size(); ++r) {
    message_.resize(maps_[r].PackedSize(global_.S));
    comm_->Recv(r, Traffic::kSubRcs, std::span<double>(message_));
    AggregateSubRcs(maps_[r], message_, &global_);
  }
  return global_;
}

// Every rank steps its own copy of its cameras by its rows of δc.
StepEvaluation MpiPointWorkers::EvaluateStep(double lambda, const std::vector<double>& delta_c) {
  BroadcastCommand(comm_, {Op::kStep, 0, lambda});
  FaultPoint(0, "step", ++steps_);
  for (int r = 1; r < comm_->size() && distributed_ == nullptr; ++r) {
    const std::vector<double> local = LocalDelta(delta_c, global_.layout, maps_[r].global_row);
    comm_->Send(r, Traffic::kCameraUpdate, std::span<const double>(local));
  }
  std::vector<double> mine(kPackedEvaluation, 0.0);
  if (own_ != nullptr) {
    const std::vector<double> local = distributed_ != nullptr
                                          ? own_delta_
                                          : LocalDelta(delta_c, global_.layout, maps_[0].global_row);
    mine = Pack(own_->EvaluateStep(lambda, local));
  }
  const std::vector<double> all = comm_->Gather(Traffic::kControl, mine);
  StepEvaluation e;
  for (int r = 0; r < comm_->size(); ++r) {
    const double* v = all.data() + kPackedEvaluation * r;
    e.model_cost += v[0];
    e.candidate_cost += v[1];
    e.point_step_squared_norm += v[2];
    e.candidate_residuals.Add({v[3], v[4], v[5]});
    e.point_spread.Merge({v[6], Vec3(v[7], v[8], v[9]), v[10]});
  }
  return e;
}

void MpiPointWorkers::FinishStep(bool accept) {
  BroadcastCommand(comm_, {Op::kFinish, accept ? 1 : 0, 0.0});
  FaultPoint(0, "finish", ++finishes_);
  if (own_ != nullptr) own_->FinishStep(accept);
}

void MpiPointWorkers::CollectPoints(std::vector<double>* points) {
  BroadcastCommand(comm_, {Op::kCollect, 0, 0.0});
  ReceivePoints(points);
}

// Every rank's points into `points`, rank by rank (after a COLLECT or an END
// that asks for them).
void MpiPointWorkers::ReceivePoints(std::vector<double>* points) {
  auto place = [&](const std::vector<int64_t>& ids, const std::vector<double>& xyz) {
    for (size_t k = 0; k < ids.size(); ++k) {
      std::copy_n(xyz.data() + kPointSize * k, kPointSize,
                  points->data() + kPointSize * ids[k]);
    }
  };
  if (own_share_ != nullptr) place(own_share_->global_point, own_share_->problem.points);
  for (int r = 1; r < comm_->size(); ++r) {
    const auto ids = comm_->RecvVector<int64_t>(r, Traffic::kResult);
    const auto xyz = comm_->RecvVector<double>(r, Traffic::kResult);
    place(ids, xyz);
  }
}

RejectionRound MpiPointWorkers::DropOutliers(const RejectionCriteria& criteria, int num_threads,
                                             ShareRejection* own_state, PoseObservations* poses) {
  BroadcastCommand(comm_, {Op::kReject, 0, criteria.max_error_px,
                           criteria.min_triangulation_angle_deg});
  std::vector<double> mine(kPackedRound, 0.0);
  if (own_ != nullptr) {
    mine = Pack(DropShareOutliers(criteria, num_threads, own_share_, own_state, poses));
  }
  const std::vector<double> all = comm_->Gather(Traffic::kControl, mine);
  for (int r = 1; r < comm_->size(); ++r) {  // each rank's poses, summed
    for (std::vector<int64_t>* counts : {&poses->before, &poses->after}) {
      const auto theirs = comm_->RecvVector<int64_t>(r, Traffic::kControl);
      if (theirs.size() > counts->size()) counts->resize(theirs.size(), 0);
      for (size_t f = 0; f < theirs.size(); ++f) (*counts)[f] += theirs[f];
    }
  }
  RejectionRound sum;
  for (int r = 0; r < comm_->size(); ++r) {
    const double* v = all.data() + kPackedRound * r;
    sum.observations_dropped += static_cast<int64_t>(v[0]);
    sum.points_dropped += static_cast<int64_t>(v[1]);
    sum.points_small_angle += static_cast<int64_t>(v[2]);
    sum.observations_left += static_cast<int64_t>(v[3]);
    sum.points_left += static_cast<int64_t>(v[4]);
  }
  return sum;
}

void MpiPointWorkers::Rebuild(bool keep_loss) {
  BroadcastCommand(comm_, {Op::kRebuild, keep_loss ? 1 : 0, 0.0});
}

std::vector<ShareLeft> MpiPointWorkers::CollectLeft(const ShareRejection* own_state) {
  BroadcastCommand(comm_, {Op::kLeft, 0, 0.0});
  std::vector<ShareLeft> left;
  if (own_ != nullptr) left.push_back(LeftOfShare(*own_share_, *own_state));
  for (int r = 1; r < comm_->size(); ++r) left.push_back(RecvLeft(comm_, r));
  return left;
}

std::vector<RankReport> MpiPointWorkers::Finish(
    std::vector<double>* points, int64_t memory_estimate_bytes,
    std::vector<std::vector<TrafficStats>>* per_iteration) {
  const bool collect = points != nullptr;
  BroadcastCommand(comm_, {Op::kEnd, collect ? 1 : 0, 0.0});
  FaultPoint(0, "end", 1);
  if (collect) ReceivePoints(points);
  std::vector<RankReport> reports(comm_->size());
  if (per_iteration != nullptr) per_iteration->assign(comm_->size(), {});
  for (int r = 1; r < comm_->size(); ++r) {
    comm_->Recv(r, Traffic::kResult, std::span<RankReport>(&reports[r], 1));
    std::vector<TrafficStats> marks = comm_->RecvVector<TrafficStats>(r, Traffic::kResult);
    marks.push_back(reports[r].traffic);
    if (per_iteration == nullptr) continue;
    for (size_t k = 1; k < marks.size(); ++k) {
      TrafficStats d;
      for (int t = 0; t < kNumTraffic; ++t) {
        d.bytes[t] = marks[k].bytes[t] - marks[k - 1].bytes[t];
        d.seconds[t] = marks[k].seconds[t] - marks[k - 1].seconds[t];
        d.wait_seconds[t] = marks[k].wait_seconds[t] - marks[k - 1].wait_seconds[t];
      }
      (*per_iteration)[r].push_back(d);
    }
  }
  reports[0] = own_share_ != nullptr
                   ? MakeRankReport(0, *own_share_, own_, *comm_, memory_estimate_bytes,
                                    distributed_.get())
                   : MakeRankReport(0, RankShare{}, nullptr, *comm_, memory_estimate_bytes,
                                    distributed_.get());
  return reports;
}

RankLoopEnd RunPointRank(Communicator* comm, RankShare* share, LocalPointWorkers* workers,
                         int64_t memory_estimate_bytes, ShareRejection* rejection,
                         RcsPlacement placement, const LinearSolverOptions& linear,
                         const DampingBounds& bounds) {
  std::unique_ptr<DistributedRcs> distributed;
  if (placement == RcsPlacement::kDistributed) {
    distributed = BuildDistributedRcs(comm, nullptr, share, workers, linear, nullptr);
    OwnedFootprint(comm, *distributed);
  } else {
    comm->SendVector(0, Traffic::kDistribution, BlockPattern(workers->system().S));
    comm->SendVector(0, Traffic::kDistribution,
                     workers->system().layout.RowEntities(share->CameraRowIds(),
                                                          share->global_intrinsics));
  }
  std::vector<double> message, delta(workers->system().layout.num_unknowns());
  int formations = 0, steps = 0, finishes = 0;
  double lambda = 0.0;
  std::vector<TrafficStats> marks;  // the traffic at each FORM
  auto send_points = [&] {
    comm->SendVector(0, Traffic::kResult, share->global_point);
    comm->SendVector(0, Traffic::kResult, share->problem.points);
  };
  for (;;) {
    Command c{};
    comm->Broadcast(Traffic::kControl, &c);
    switch (c.op) {
      case Op::kForm:
        marks.push_back(comm->stats());
        FaultPoint(comm->rank(), "form", ++formations);
        if (distributed != nullptr) {
          distributed->Reduce(&workers->FormRcs(c.lambda), c.accept == 1);
          workers->ReleaseRcsValues();  // summed into the owners' rows
          break;
        }
        PackSubRcs(workers->FormRcs(c.lambda), &message);
        comm->Send(0, Traffic::kSubRcs, std::span<const double>(message));
        break;
      case Op::kSolve:
        if (distributed == nullptr) throw std::runtime_error("SOLVE with the RCS gathered");
        if (c.accept == 1) distributed->DropDampingFloor();
        distributed->Solve(c.lambda, bounds);
        distributed->SpreadStep(&delta, nullptr);
        break;
      case Op::kStep: {
        FaultPoint(comm->rank(), "step", ++steps);
        lambda = c.lambda;
        if (distributed == nullptr) comm->Recv(0, Traffic::kCameraUpdate, std::span<double>(delta));
        comm->Gather(Traffic::kControl, Pack(workers->EvaluateStep(lambda, delta)));
        break;
      }
      case Op::kFinish:
        FaultPoint(comm->rank(), "finish", ++finishes);
        workers->FinishStep(c.accept != 0);
        break;
      case Op::kCollect:
        send_points();
        break;
      case Op::kReject: {
        PoseObservations poses;
        comm->Gather(Traffic::kControl,
                     Pack(DropShareOutliers({c.lambda, c.value}, workers->num_threads(), share,
                                            rejection, &poses)));
        comm->SendVector(0, Traffic::kControl, poses.before);
        comm->SendVector(0, Traffic::kControl, poses.after);
        break;
      }
      case Op::kRebuild:
        return {true, c.accept != 0};
      case Op::kLeft:
        SendLeft(comm, LeftOfShare(*share, *rejection));
        break;
      case Op::kEnd: {
        FaultPoint(comm->rank(), "end", 1);
        if (c.accept != 0) send_points();  // the main rank wants the points
        const RankReport report = MakeRankReport(comm->rank(), *share, workers, *comm,
                                                 memory_estimate_bytes, distributed.get());
        comm->Send(0, Traffic::kResult, std::span<const RankReport>(&report, 1));
        comm->SendVector(0, Traffic::kResult, marks);
        return {};
      }
      default:
        throw std::runtime_error("unknown command from the main rank");
    }
  }
}

}  // namespace dba
