// PointWorkers spread over MPI ranks: the iteration protocol of docs/design.md §4.
//
// The RCS is gathered on the main rank (RcsPlacement::kGather, the paper's)
// or spread over the ranks (kDistributed, cluster/distributed_rcs.h):
//
//   main rank (MpiPointWorkers)            every rank (RunPointRank, or the
//                                          main rank's own share)
//   FormRcs:   broadcast FORM(λ)      ─►   form sub-RCS (local ids) + rhs
//     gather:  receive rank by rank   ◄─   packed values
//              add into global BSMC (indexed add, one message at a time)
//     distributed:                         reduce-scatter to the rows' owners
//   Solve (distributed only): broadcast SOLVE(λ) ─► damp own rows, PCG
//              across the ranks, δc of its rows from their owners; all of
//              δc to the main rank
//   EvaluateStep: broadcast STEP(λ),
//              (gather) send δc of its rows ─► back-substitute, costs at the step
//              gather partial sums    ◄─   7 numbers
//   FinishStep: broadcast FINISH(accept) ─► keep or drop the candidate
//   CollectPoints: broadcast COLLECT  ─►   (between iterations, checkpoints)
//              receive rank by rank   ◄─   global ids, points
//   DropOutliers: broadcast REJECT    ─►   drop from the share (between solves)
//              gather the round       ◄─   5 counts
//   Rebuild:   broadcast REBUILD      ─►   new workers, pattern sent again
//   CollectLeft: broadcast LEFT       ─►   what is left of the loaded share
//
// Sub-RCSs are summed in rank order, so a run is reproducible. The numerical
// work is LocalPointWorkers on each rank's share; this file only moves data.
//
// Thread safety: one caller per rank.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "dba/cluster/aggregate_sub_rcs.h"
#include "dba/cluster/communicator.h"
#include "dba/common/fault_seam.h"
#include "dba/cluster/distributed_rcs.h"
#include "dba/cluster/rank_share.h"
#include "dba/cluster/share_outliers.h"
#include "dba/lm/bundle_adjust.h"
#include "dba/lm/local_point_workers.h"

namespace dba {

// What every rank reports about its share at the end of a solve.
struct RankReport {
  int rank = 0;
  int64_t points = 0;
  int64_t observations = 0;
  int64_t cameras = 0;
  int64_t sub_rcs_blocks = 0;
  int64_t sub_rcs_bytes = 0;  // BSMC structure + values
  int64_t peak_memory_bytes = 0;
  int64_t memory_estimate_bytes = 0;  // before its RCS's values (lm/memory_estimate.h)
  int64_t traffic_bytes = 0;
  // Distributed RCS: the rows this rank owns, their stored blocks and bytes
  // (structure and values), and its halo rows.
  int64_t owned_rows = 0;
  int64_t owned_blocks = 0;
  int64_t owned_bytes = 0;
  int64_t halo_rows = 0;
  TrafficStats traffic;  // this rank's, whole solve
};

// Where the RCS lives: gathered on the main rank, or spread over the ranks.
enum class RcsPlacement { kGather, kDistributed };
const char* RcsPlacementName(RcsPlacement placement);

class MpiPointWorkers : public PointWorkers {
 public:
  // Symbolic phase on the main rank: receives every other rank's sub-RCS
  // pattern and the global ids of its rows, builds the global RCS over the
  // unknowns of `layout` (the whole problem's) and the block maps. `own` (may
  // be null) is the main rank's own share.
  // `before_values`: called with the global RCS's structure before its
  // values are allocated (RcsSystem::ForProblem).
  // Distributed (`placement`): the ranks agree on the rows' owners and
  // build their parts of the RCS and the PCG storage from `linear` and
  // `bounds`; the main rank holds none of S. `cameras` (distributed, two-
  // level preconditioner): the camera-side parameters, for its bases.
  MpiPointWorkers(Communicator* comm, UnknownLayout layout, RankShare* own_share,
                  LocalPointWorkers* own,
                  const std::function<void(const RcsSystem&)>& before_values = {},
                  RcsPlacement placement = RcsPlacement::kGather,
                  const LinearSolverOptions& linear = {}, const DampingBounds& bounds = {},
                  const double* cameras = nullptr);
  ~MpiPointWorkers() override;

  // Gathered: the global system. Distributed: the layout, cost and residual
  // sums of all ranks, camera_side_gradient one entry (‖g_c‖∞ over all
  // ranks) and S empty.
  RcsSystem& FormRcs(double lambda) override;
  std::unique_ptr<DampedRcsSolver> MakeDampedRcsSolver(RcsSystem& system,
                                                       const LinearSolverOptions& options,
                                                       RcsSolverChoice* choice) override;
  StepEvaluation EvaluateStep(double lambda, const std::vector<double>& delta_c) override;
  void FinishStep(bool accept) override;
  // Distributed: the owners add the pose terms at the next FormRcs.
  bool TakesPoseTerms() const override { return distributed_ != nullptr; }
  void SetPoseTerms(std::vector<PoseRowTerm> terms) override { pose_terms_ = std::move(terms); }

  // Between iterations: every rank's current points into `points` (global
  // numbering; sized to hold all), for a checkpoint.
  void CollectPoints(std::vector<double>* points);

  // --reject-outliers (cluster/share_outliers.h), between solves: every
  // rank drops from its share (the main rank from its own, `own_state`);
  // the round summed over the ranks, and into `poses` each pose's
  // observations before and after it, summed too. Then either Rebuild (every rank's
  // workers are stale: the caller makes new ones, the ranks too, and the
  // next solve runs with the loss or the squared one) or CollectLeft and
  // Finish.
  RejectionRound DropOutliers(const RejectionCriteria& criteria, int num_threads,
                              ShareRejection* own_state, PoseObservations* poses);
  void Rebuild(bool keep_loss);
  // What is left of every share (the main rank's first, if it forms).
  std::vector<ShareLeft> CollectLeft(const ShareRejection* own_state);

  // Ends the other ranks' loops and collects their reports; with `points`
  // non-null also their final points (global numbering; resized to hold all).
  // `memory_estimate_bytes`: the main rank's, for its report.
  // `per_iteration` (optional): each rank's traffic per formation (from one
  // FORM to the next, the last to the end), rank by rank; the main rank's
  // entry is left empty (its caller counts its own per LM iteration).
  std::vector<RankReport> Finish(std::vector<double>* points, int64_t memory_estimate_bytes = 0,
                                 std::vector<std::vector<TrafficStats>>* per_iteration = nullptr);

  const RcsSystem& global() const { return global_; }
  RcsPlacement placement() const { return placement_; }
  // The RCS's size: the global matrix's, or the owners' parts summed.
  const RcsFootprint& footprint() const { return footprint_; }

 private:
  class DistributedSolver;
  void ReceivePoints(std::vector<double>* points);

  Communicator* comm_;
  RankShare* own_share_;
  LocalPointWorkers* own_;
  int steps_ = 0, finishes_ = 0;  // for the fault points (common/fault_seam.h)
  std::vector<SubRcsMap> maps_;  // per rank; maps_[0] is the main rank's own
  RcsSystem global_;
  std::vector<double> message_;
  int formations_ = 0;
  RcsPlacement placement_ = RcsPlacement::kGather;
  std::unique_ptr<DistributedRcs> distributed_;
  DampingBounds bounds_;
  std::vector<double> own_delta_;  // distributed: δc of the own share's rows
  std::vector<PoseRowTerm> pose_terms_;  // distributed: for the next FormRcs
  RcsFootprint footprint_;
};

// How a rank's loop ended: the solve is over, or (REBUILD) the share changed
// and the caller builds new workers and serves again.
struct RankLoopEnd {
  bool rebuild = false;
  bool keep_loss = false;  // the next solve's loss: the same, or squared
};

// The loop of a rank other than the main one: serves FORM, STEP, FINISH,
// COLLECT, REJECT and LEFT until the main rank ends the solve (then sends
// its points and report) or asks for a REBUILD. Throws on failure (the
// caller aborts the job). `memory_estimate_bytes` goes into its report;
// `rejection`: the share's state across rejection rounds.
// `placement`, `linear`, `bounds`: as the main rank's MpiPointWorkers.
RankLoopEnd RunPointRank(Communicator* comm, RankShare* share, LocalPointWorkers* workers,
                         int64_t memory_estimate_bytes, ShareRejection* rejection,
                         RcsPlacement placement = RcsPlacement::kGather,
                         const LinearSolverOptions& linear = {},
                         const DampingBounds& bounds = {});

// Report of this rank's share (peak memory read now).
RankReport MakeRankReport(int rank, const RankShare& share,
                          const LocalPointWorkers* workers, const Communicator& comm,
                          int64_t memory_estimate_bytes = 0,
                          const DistributedRcs* distributed = nullptr);

}  // namespace dba
