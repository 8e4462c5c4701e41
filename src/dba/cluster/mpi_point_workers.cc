// The distributed iteration protocol; see mpi_point_workers.h.
#include "dba/cluster/mpi_point_workers.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include "dba/common/memory.h"

namespace dba {
namespace {

enum class Op : int32_t {
  kForm = 1, kStep = 2, kFinish = 3, kEnd = 4, kCollect = 5, kReject = 6, kRebuild = 7, kLeft = 8
};

struct Command {
  Op op;
  int32_t accept;  // FINISH: accept; END: send points; REBUILD: keep the loss
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

// A share's cameras ⊞ its δc.
std::vector<double> Plus(const LocalPointWorkers& workers, const std::vector<double>& cameras,
                         const std::vector<double>& delta) {
  std::vector<double> out(cameras.size());
  workers.system().layout.Plus(cameras.data(), delta.data(), out.data());
  return out;
}

constexpr int kPackedEvaluation = 7;  // values of Pack(StepEvaluation)

std::vector<double> Pack(const StepEvaluation& e) {
  return {e.model_cost, e.candidate_cost, e.point_step_squared_norm, e.point_squared_norm,
          e.candidate_residuals.squared, e.candidate_residuals.inlier_squared,
          e.candidate_residuals.inliers};
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

}  // namespace

void MaybeInjectFault(int rank, const char* step, int count) {
  const char* spec = std::getenv("DBA_INJECT_FAULT");
  if (spec == nullptr) return;
  int fault_rank = -1, fault_count = -1;
  char fault_step[16] = "form";
  const bool parsed =
      std::sscanf(spec, "%d:%15[a-z]:%d", &fault_rank, fault_step, &fault_count) == 3 ||
      std::sscanf(spec, "%d:%d", &fault_rank, &fault_count) == 2;
  if (parsed && fault_rank == rank && fault_count == count && std::strcmp(fault_step, step) == 0) {
    throw std::runtime_error("injected fault (DBA_INJECT_FAULT=" + std::string(spec) + ") at " +
                             step + " " + std::to_string(count));
  }
}

RankReport MakeRankReport(int rank, const RankShare& share,
                          const LocalPointWorkers* workers, const Communicator& comm,
                          int64_t memory_estimate_bytes) {
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
  r.peak_memory_bytes = PeakResidentBytes();
  r.traffic_bytes = comm.stats().total_bytes();
  return r;
}

MpiPointWorkers::MpiPointWorkers(Communicator* comm, UnknownLayout layout,
                                 RankShare* own_share, LocalPointWorkers* own,
                                 const std::function<void(const RcsSystem&)>& before_values)
    : comm_(comm), own_share_(own_share), own_(own) {
  // Every rank's sub-RCS pattern in global numbering; the global pattern is
  // their union (plus every diagonal block).
  std::vector<std::vector<uint64_t>> local_patterns(comm->size());
  std::vector<std::vector<int32_t>> rows(comm->size());
  if (own != nullptr) {
    local_patterns[0] = BlockPattern(own->system().S);
    rows[0] = layout.RowsOfEntities(own->system().layout.RowEntities(
        own_share->global_camera, own_share->global_intrinsics));
  }
  for (int r = 1; r < comm->size(); ++r) {
    local_patterns[r] = comm->RecvVector<uint64_t>(r, Traffic::kDistribution);
    rows[r] = layout.RowsOfEntities(comm->RecvVector<int64_t>(r, Traffic::kDistribution));
  }
  GlobalRcs global =
      BuildGlobalRcs(std::move(layout), local_patterns, std::move(rows), before_values);
  global_ = std::move(global.system);
  maps_ = std::move(global.maps);
}

RcsSystem& MpiPointWorkers::FormRcs(double lambda) {
  BroadcastCommand(comm_, {Op::kForm, 0, lambda});
  ++formations_;
  ClearRcs(&global_);
  if (own_ != nullptr) {
    MaybeInjectFault(0, "form", formations_);
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

StepEvaluation MpiPointWorkers::EvaluateStep(double lambda,
                                             const std::vector<double>& delta_c,
                                             const std::vector<double>& candidate_cameras) {
  (void)candidate_cameras;  // ranks add δc to their own copies of the cameras
  BroadcastCommand(comm_, {Op::kStep, 0, lambda});
  MaybeInjectFault(0, "step", ++steps_);
  for (int r = 1; r < comm_->size(); ++r) {
    const std::vector<double> local = LocalDelta(delta_c, global_.layout, maps_[r].global_row);
    comm_->Send(r, Traffic::kCameraUpdate, std::span<const double>(local));
  }
  std::vector<double> mine(kPackedEvaluation, 0.0);
  if (own_ != nullptr) {
    const std::vector<double> local = LocalDelta(delta_c, global_.layout, maps_[0].global_row);
    mine = Pack(own_->EvaluateStep(lambda, local, Plus(*own_, own_share_->problem.cameras, local)));
  }
  const std::vector<double> all = comm_->Gather(Traffic::kControl, mine);
  StepEvaluation e;
  for (int r = 0; r < comm_->size(); ++r) {
    const double* v = all.data() + kPackedEvaluation * r;
    e.model_cost += v[0];
    e.candidate_cost += v[1];
    e.point_step_squared_norm += v[2];
    e.point_squared_norm += v[3];
    e.candidate_residuals.Add({v[4], v[5], v[6]});
  }
  return e;
}

void MpiPointWorkers::FinishStep(bool accept) {
  BroadcastCommand(comm_, {Op::kFinish, accept ? 1 : 0, 0.0});
  MaybeInjectFault(0, "finish", ++finishes_);
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
                                             ShareRejection* own_state) {
  BroadcastCommand(comm_, {Op::kReject, 0, criteria.max_error_px,
                           criteria.min_triangulation_angle_deg});
  std::vector<double> mine(kPackedRound, 0.0);
  if (own_ != nullptr) {
    mine = Pack(DropShareOutliers(criteria, num_threads, own_share_, own_state));
  }
  const std::vector<double> all = comm_->Gather(Traffic::kControl, mine);
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

std::vector<RankReport> MpiPointWorkers::Finish(std::vector<double>* points,
                                                int64_t memory_estimate_bytes) {
  const bool collect = points != nullptr;
  BroadcastCommand(comm_, {Op::kEnd, collect ? 1 : 0, 0.0});
  MaybeInjectFault(0, "end", 1);
  if (collect) ReceivePoints(points);
  std::vector<RankReport> reports(comm_->size());
  for (int r = 1; r < comm_->size(); ++r) {
    comm_->Recv(r, Traffic::kResult, std::span<RankReport>(&reports[r], 1));
  }
  reports[0] = own_share_ != nullptr
                   ? MakeRankReport(0, *own_share_, own_, *comm_, memory_estimate_bytes)
                   : MakeRankReport(0, RankShare{}, nullptr, *comm_, memory_estimate_bytes);
  return reports;
}

RankLoopEnd RunPointRank(Communicator* comm, RankShare* share, LocalPointWorkers* workers,
                         int64_t memory_estimate_bytes, ShareRejection* rejection) {
  comm->SendVector(0, Traffic::kDistribution, BlockPattern(workers->system().S));
  comm->SendVector(0, Traffic::kDistribution,
                   workers->system().layout.RowEntities(share->global_camera,
                                                        share->global_intrinsics));
  std::vector<double> message, delta(workers->system().layout.num_unknowns());
  int formations = 0, steps = 0, finishes = 0;
  double lambda = 0.0;
  auto send_points = [&] {
    comm->SendVector(0, Traffic::kResult, share->global_point);
    comm->SendVector(0, Traffic::kResult, share->problem.points);
  };
  for (;;) {
    Command c{};
    comm->Broadcast(Traffic::kControl, &c);
    switch (c.op) {
      case Op::kForm:
        MaybeInjectFault(comm->rank(), "form", ++formations);
        PackSubRcs(workers->FormRcs(c.lambda), &message);
        comm->Send(0, Traffic::kSubRcs, std::span<const double>(message));
        break;
      case Op::kStep: {
        MaybeInjectFault(comm->rank(), "step", ++steps);
        lambda = c.lambda;
        comm->Recv(0, Traffic::kCameraUpdate, std::span<double>(delta));
        const StepEvaluation e = workers->EvaluateStep(
            lambda, delta, Plus(*workers, share->problem.cameras, delta));
        comm->Gather(Traffic::kControl, Pack(e));
        break;
      }
      case Op::kFinish:
        MaybeInjectFault(comm->rank(), "finish", ++finishes);
        workers->FinishStep(c.accept != 0);
        break;
      case Op::kCollect:
        send_points();
        break;
      case Op::kReject:
        comm->Gather(Traffic::kControl,
                     Pack(DropShareOutliers({c.lambda, c.value}, workers->num_threads(), share,
                                            rejection)));
        break;
      case Op::kRebuild:
        return {true, c.accept != 0};
      case Op::kLeft:
        SendLeft(comm, LeftOfShare(*share, *rejection));
        break;
      case Op::kEnd: {
        MaybeInjectFault(comm->rank(), "end", 1);
        if (c.accept != 0) send_points();  // the main rank wants the points
        const RankReport report =
            MakeRankReport(comm->rank(), *share, workers, *comm, memory_estimate_bytes);
        comm->Send(0, Traffic::kResult, std::span<const RankReport>(&report, 1));
        return {};
      }
      default:
        throw std::runtime_error("unknown command from the main rank");
    }
  }
}

}  // namespace dba
