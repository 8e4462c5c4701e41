// Distributed bundle adjustment (paper section 6, docs/design.md §4): the main
// rank partitions the points, sends each rank its share, and runs LM over
// MpiPointWorkers; every other rank serves its share until the solve ends.
//
// Thread safety: collective over the communicator; one call per process.
#pragma once

#include "dba/lm/prior_workers.h"

#include <functional>
#include <string>
#include <vector>

#include "dba/cluster/communicator.h"
#include "dba/cluster/mpi_point_workers.h"
#include "dba/cluster/partition.h"
#include "dba/io/checkpoint.h"
#include "dba/lm/bundle_adjust.h"
#include "dba/lm/memory_estimate.h"
#include "dba/lm/outlier_rejection.h"
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
  // --reject-outliers: rounds of rejection and solving again after the
  // first solve (lm/outlier_rejection.h), each rank on its share; the solves
  // after it with the loss (keep_loss) or the squared one.
  bool reject_outliers = false;
  RejectionCriteria rejection;
  bool reject_keep_loss = false;
  // Camera-centre priors (lm/prior_workers.h), global image numbering: the
  // main rank computes their terms and adds them to the gathered RCS, or
  // sends them to their rows' owners (distributed).
  CameraPriors priors;
  // Where the RCS lives (--rcs): auto spreads it over the ranks when there
  // is more than one and the linear solve is PCG (auto or pcg); else gathers
  // it.
  enum class Rcs { kAuto, kGather, kDistributed } rcs = Rcs::kAuto;
};

// The placement `options` ask for on `ranks` ranks; throws std::invalid_argument when
// kDistributed cannot be had (a factorization).
RcsPlacement ChooseRcsPlacement(const DistributedOptions& options, const LmOptions& lm, int ranks);

struct DistributedSummary {
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
  // With reject_outliers (main rank): the rounds, and what is left of the
  // loaded problem; the solves after them are appended to `ba`.
  std::vector<RejectionRound> rejection;
  KeptObservations kept;
};

// Checkpoints of a distributed solve (io/checkpoint.h); the main rank's.
struct DistributedCheckpoints {
  // Written after accepted iterations, with the points gathered from the
  // ranks (24 bytes per point on the main rank while it is written).
  CheckpointWriter* writer = nullptr;
  // A binary input read by the ranks: the checkpoint to start from, checked
  // against the problem the ranks read (fingerprint), then handed out. (With
  // the whole problem on the main rank, the caller applies it before.) Its
  // parameters are released once handed out.
  Checkpoint* resume = nullptr;
  std::string resume_path;  // for the message when it does not fit
};

// What the main rank hears during the solve.
struct DistributedHooks {
  std::function<void(const IterationSummary&)> on_iteration;
  std::function<void(int, const RejectionRound&)> on_rejection_round;
  DistributedCheckpoints checkpoints;
};

// Collective. Two ways to get the points to the ranks:
//  - `binary_input` empty: on the main rank `problem` is the whole problem;
//    the main rank partitions it and sends each rank its share, then
//    releases the observations.
//  - `binary_input` a dba binary file: every rank reads only its own points
//    and their observations from it; the main rank streams the visibility
//    graph to partition (camera-locality scheme) and reads cameras and point
//    coordinates into `problem`, never the observations.
// On return the main rank's `problem` holds the adjusted cameras and, if
// `collect_points`, the adjusted points (no observations). `problem` is
// ignored on the other ranks.
DistributedSummary DistributedBundleAdjust(
    Communicator* comm, const LmOptions& options, const DistributedOptions& distributed,
    const std::string& binary_input, bool collect_points, Problem* problem,
    const DistributedHooks& hooks = {});

}  // namespace dba
