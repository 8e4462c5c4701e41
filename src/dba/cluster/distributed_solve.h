// Distributed bundle adjustment (paper section 6, docs/design.md §4): the main
// rank partitions the points, sends each rank its share, and drives them
// through MpiPointWorkers (DistributedPointSide: the solve session runs LM,
// rejection rounds and checkpoints over it); every other rank serves its
// share until the solve ends (ServePoints).
//
// Thread safety: collective over the communicator; one call per process.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "dba/cluster/communicator.h"
#include "dba/cluster/mpi_point_workers.h"
#include "dba/cluster/partition.h"
#include "dba/io/checkpoint.h"
#include "dba/lm/bundle_adjust.h"
#include "dba/lm/memory_estimate.h"
#include "dba/cluster/share_outliers.h"
#include "dba/lm/local_point_workers.h"
#include "dba/lm/outlier_rejection.h"
#include "dba/lm/point_side.h"
#include "dba/camera/pose_similarity.h"
#include "dba/problem/fixings.h"

namespace dba {

struct DistributedOptions {
  PartitionScheme partition = PartitionScheme::kCameraLocality;
  // Whether the main rank also forms a sub-RCS from a share of the points.
  // Auto: yes for up to kMainFormsUpTo ranks, where an idle main rank would
  // waste a large fraction of the machine.
  enum class MainRole { kAuto, kForms, kCoordinates } main_role = MainRole::kAuto;
  static constexpr int kMainFormsUpTo = 4;
  // With a binary input read by every rank: held fixed by every rank in the
  // camera side it reads (global numbering), before its share is cut out.
  Fixings fixings;
  // Each rank refuses (the job stops) when its estimated growth exceeds its
  // part of the node's available memory (available / ranks on the node).
  bool memory_check = true;
  // Where the RCS lives (--rcs): auto spreads it over the ranks when there
  // is more than one and the linear solve is PCG (auto or pcg); else gathers
  // it.
  enum class Rcs { kAuto, kGather, kDistributed } rcs = Rcs::kAuto;
  // The camera priors' lever arm is an unknown: its row meets every camera
  // row, which only a gathered RCS holds (auto gathers; kDistributed is
  // refused).
  bool lever_arm_row = false;
};

// The placement `options` ask for on `ranks` ranks; throws std::invalid_argument when
// kDistributed cannot be had (a factorization, a refined lever arm).
RcsPlacement ChooseRcsPlacement(const DistributedOptions& options, const LmOptions& lm, int ranks);

// A solve on one or more ranks (one: a one-process solve, the distributed
// figures left at their defaults): the LM's summary, and how the points and
// the RCS were spread and what went between the ranks.
struct SolveOnRanksSummary {
  BundleAdjustSummary ba;
  int ranks = 1;
  bool main_forms = true;
  PartitionScheme partition = PartitionScheme::kCameraLocality;
  RcsPlacement rcs = RcsPlacement::kGather;
  std::vector<RankReport> rank_reports;     // main rank only
  TrafficStats traffic;                     // main rank's, whole solve
  std::vector<TrafficStats> per_iteration;  // main rank's, per LM iteration
  // The other ranks', per formation (rank_per_iteration[r], r >= 1).
  std::vector<std::vector<TrafficStats>> rank_per_iteration;
  double distribution_seconds = 0.0;        // partition + sending the shares
  // The main rank's estimate before the global RCS's values (its own
  // share's sub-RCS, if it forms, already held); total 0: not estimated.
  MemoryEstimate memory_estimate;
};

// Checkpoints of a distributed solve whose ranks read a .dba themselves: the
// checkpoint to start from, checked against the problem the ranks read
// (fingerprint), then handed out (its parameters released once handed
// out); and the writer, which gets the fingerprint summed over the ranks.
// (With the whole problem on the main rank, the caller applies it before.)
struct DistributedCheckpoints {
  CheckpointWriter* writer = nullptr;
  Checkpoint* resume = nullptr;
  std::string resume_path;  // for the message when it does not fit
};

// The points of a solve spread over MPI ranks, as the main rank drives them
// (the other ranks run ServePoints). Collective construction, two ways to
// get the points to the ranks:
//  - `binary_input` empty: `problem` is the whole problem; the main rank
//    partitions it and sends each rank its share, then releases the
//    observations;
//  - `binary_input` a dba binary file: every rank reads only its own points
//    and their observations from it; the main rank streams the visibility
//    graph to partition (camera-locality scheme) and reads cameras and point
//    coordinates into `problem`, never the observations.
// `problem` then holds the cameras the LM loop updates.
// With `binary_input`, `problem` is the camera side as the caller prepared
// it (fixings, and when georeferenced its cameras aligned and the control
// points appended as its only points); `alignment`, the similarity that
// moved the cameras, is applied to every rank's points as they are read,
// and the control points join the main rank's share (rank 1's when the
// main rank does not form). The main rank never holds the file's
// observations.
class DistributedPointSide : public PointSide {
 public:
  DistributedPointSide(Communicator* comm, const LmOptions& options,
                       const DistributedOptions& distributed, const std::string& binary_input,
                       Problem* problem, const DistributedCheckpoints& checkpoints = {},
                       const std::optional<Similarity>& alignment = std::nullopt,
                       const std::optional<std::vector<int64_t>>& walk = std::nullopt);
  ~DistributedPointSide() override;

  // LM over every rank's points from the current parameters with `options`
  // (its loss: the workers are made again after a rejection round), the
  // priors' terms added on the main rank; `on_iteration` hears each
  // iteration (between iterations the main rank may collect the points).
  // Each rank checks its own memory (DistributedOptions::memory_check):
  // `before_values` is not called.
  BundleAdjustSummary Solve(const LmOptions& options, const CameraPriors& priors,
                            const IterationHook& on_iteration,
                            const std::function<void(const RcsSystem&)>& before_values = {})
      override;
  // One round of outlier rejection on every rank's share (the next Solve
  // rebuilds the workers on what is left, with `keep_loss`'s loss); each
  // pose's observations before and after it into `poses`, over every rank.
  RejectionRound DropOutliers(const RejectionCriteria& criteria, int num_threads,
                              bool keep_loss, PoseObservations* poses) override;
  // After the last Solve: the RCS at the current parameters over every
  // rank (lm/solve_with_priors.h's FormAtCurrentParameters) handed to
  // `look`: gathered, all of S; spread, S stays with its rows' owners.
  void AtOptimum(const LmOptions& options, const CameraPriors& priors,
                 const std::function<void(const RcsSystem&)>& look) override;
  // Every rank's current points, in global numbering (points dropped keep
  // their last values).
  void AllPoints(std::vector<double>* points) override;
  // What is left, over the problem as distributed (after DropOutliers).
  KeptObservations Kept() override;
  // The main rank's cameras (the LM loop's, current between iterations).
  void AllCameras(std::vector<double>* cameras) override { *cameras = problem_->cameras; }
  // Ends the other ranks; with `collect_points` the final points into the
  // problem (global numbering). The distributed figures into `summary`.
  void Finish(bool collect_points, SolveOnRanksSummary* summary);

  int64_t num_points() const { return num_points_; }
  int64_t num_observations() const { return num_observations_; }

 private:
  void Distribute(const std::string& binary_input, const DistributedCheckpoints& checkpoints,
                  const std::optional<Similarity>& alignment,
                  const std::optional<std::vector<int64_t>>& walk);
  void ReadShares(const std::string& binary_input, const DistributedCheckpoints& checkpoints,
                  const std::optional<Similarity>& alignment);
  // `lever_arm`: the global layout has the camera priors' lever arm's row.
  void MakeWorkers(const LmOptions& options, bool lever_arm);
  // The workers, made again (on every rank) after a rejection round.
  void CurrentWorkers(const LmOptions& options, const CameraPriors& priors);

  Communicator* comm_;
  DistributedOptions distributed_;
  Problem* problem_;
  SolveOnRanksSummary summary_;
  RankShare own_;
  RankShare* mine_ = nullptr;
  int groups_ = 1;
  int64_t num_points_ = 0, num_observations_ = 0;
  LinearSolverOptions linear_;
  std::unique_ptr<LocalPointWorkers> own_workers_;
  std::vector<double> points_;  // collected: dropped points keep their values
  std::unique_ptr<MpiPointWorkers> workers_;
  MemoryEstimate own_estimate_;
  ShareRejection own_rejection_;
  bool stale_ = false;  // a rejection round since the workers were made
  bool keep_loss_ = false;
};

// The other ranks' side of a DistributedPointSide: their share read or
// received, served until the main rank ends (again with new workers after
// each rejection round). Collective.
void ServePoints(Communicator* comm, const LmOptions& options, const DistributedOptions& distributed,
                 const std::string& binary_input, const DistributedCheckpoints& checkpoints = {});

}  // namespace dba
