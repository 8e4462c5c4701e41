// One solve, whichever way it is started: the command line in one process
// or on N ranks, and Python (on a file or on arrays) all run this session.
// It owns what decides the result: the LM run on a point side that is local
// or spread over MPI ranks, camera priors and control points (geo/), rounds
// of outlier rejection, checkpoints and resume, the memory check, the
// comparison with a ground truth, and the report. The caller loads the
// input before it and writes the outputs after it (session/solve_outputs.h).
//
//   main rank                                  other ranks
//   SolveInput (LoadSolveInput, or arrays)      -
//   Run: Prepare (checks, walk, gauge's         Run: Solve (serve their
//          reference, georeference, resume)          points until the
//        Solve (LM + rejection rounds)               main rank's finish)
//        Analyse (the RCS at the optimum,
//          ranks alive; SetAnalysis)
//        FinishSolve (the ranks end)
//        HoldGauge, Measure (control points
//          out, accuracy, ground truth)
//
// Thread safety: one session per process at a time (collective over the
// communicator).
#pragma once

#include <functional>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "dba/camera/gauge_hold.h"
#include "dba/cluster/communicator.h"
#include "dba/geo/georeference.h"
#include "dba/io/checkpoint.h"
#include "dba/io/image_names.h"
#include "dba/io/input_source.h"
#include "dba/lm/outlier_rejection.h"
#include "dba/problem/problem.h"
#include "dba/session/solve_options.h"
#include "dba/cluster/distributed_solve.h"
#include "dba/lm/point_side.h"
#include "dba/precision/camera_covariance.h"
#include "dba/session/solve_report.h"

namespace dba {

// What a solve starts from, on the main rank.
struct SolveInput {
  std::string name;  // the input's path ("<arrays>" for Python's arrays)
  InputSource source;  // what the path holds, decided once (io/input_source.h)
  // The problem, with its fixings applied; empty when the ranks read
  // `name`, a .dba, themselves (ranks_read_file).
  Problem problem;
  bool ranks_read_file = false;
  ImageNames names;  // a COLMAP input's image names (empty otherwise)
  ColmapCameraCounts colmap_cameras;  // a COLMAP input's (zero otherwise)
  double read_seconds = 0.0;  // the wall time reading it took (the report's `read`)
};

// The threads of each rank: -t, else the node's cores divided by its ranks.
int ThreadsPerRank(int asked, const Communicator& comm);

// Reads options.input on the main rank: the whole problem, or, when every
// rank of a distributed run reads its own points of a .dba, only its counts.
// Fixings are checked against it (UsageError). Reading takes the rank's
// threads (a .bz2's blocks and BAL text are read in parallel).
SolveInput LoadInput(const SolveOptions& options, const InputSource& source, Communicator* comm);

// What the main rank holds after the solve.
struct SolveResult {
  SolveReport report;
  // The adjusted cameras and the points left (after rejection, those kept,
  // in their loaded order); the observations too unless the ranks held them.
  Problem problem;
  // After --reject-outliers: what is left, flagged over the problem as
  // loaded, and every loaded point (the kept ones adjusted).
  std::optional<KeptObservations> kept;
  std::vector<double> all_points;
  Georeference geo;  // the frame and priors (--output-crs, --camera-centres)
  ImageNames names;  // the input's (SolveInput::names)
  InputSource source;  // SolveInput::source
  // --covariance: the images' pose covariances at the optimum, in the
  // solve's frame before the gauge's hold moved it by `gauge_moved`.
  std::optional<CameraCovariances> covariance;
  // --point-covariance: each point's 3×3 (the points solved last, loaded
  // order; control points last), in the same frame.
  std::vector<Eigen::Matrix3d> point_covariance;
  // Why --covariance failed after the solve (the solve's own outputs are
  // still written; RunSolve then fails with it); empty: it did not.
  std::string covariance_error;
  Similarity gauge_moved;
  bool ranks_read_file = false;  // SolveInput::ranks_read_file
};

class SolveSession {
 public:
  SolveSession(const SolveOptions& options, Communicator* comm, std::ostream& log);

  // Collective. On the main rank `input` is what LoadInput returned (or a
  // problem made from arrays); other ranks pass an empty one. Returns the
  // result on the main rank (an empty one elsewhere).
  SolveResult Run(SolveInput input);

  // The optimum as the analyse stage sees it (main rank): the camera side
  // (the points too in one process) and the RCS there. Valid during the
  // call only.
  struct OptimumView {
    const Problem& problem;
    const RcsSystem& rcs;
  };
  // Called in the analyse stage of the next Run (none by default: the stage
  // then costs nothing).
  void SetAnalysis(std::function<void(const OptimumView&)> analysis) {
    analysis_ = std::move(analysis);
  }

 private:
  using IterationHook = std::function<void(const IterationSummary&)>;
  void Prepare();
  void Start(const SolveInput& input);
  void Resume();
  void ResumeRejection(Checkpoint* checkpoint);
  void PrepareGeoreferencing();
  void PrintStart();
  void Solve();
  void Analyse();
  void TakeCovariance(const Problem& problem, const RcsSystem& rcs);
  void CheckCovarianceRequest() const;
  void VarianceFactor(const UnknownLayout& layout, int free);
  void SayUndetermined(const CameraCovariances& covariances);
  void ControlPointSigmas(const Problem& problem, const UnknownLayout& layout,
                          const CameraSideInverse& inverse);
  std::unique_ptr<PointSide> MakePointSide();
  void RejectionRounds(PointSide* side, const IterationHook& log,
                       std::function<void(const RcsSystem&)> check_memory);
  void FinishSolve(PointSide* side);
  void KeepLeverArm(const BundleAdjustSummary& ba);
  void TakeLeverArm(Checkpoint* c);
  std::function<void(const RcsSystem&)> MemoryCheck();
  LmOptions RoundOptions(bool resumed_round) const;
  void HoldGauge();
  void Measure();
  void CompareWithTruth();
  IterationHook IterationLog(PointSide* side);
  void WriteCheckpoint(const IterationSummary& it, PointSide* side);
  void LoadedKeptAndPoints(PointSide* side, KeptObservations* kept, std::vector<double>* points);

  const SolveOptions& options_;
  Communicator* comm_;
  std::ostream& out_;
  LmOptions lm_;
  SolveInput input_;
  SolveResult result_;
  SetupFingerprint setup_;             // what shapes the result (io/checkpoint.h)
  std::optional<Checkpoint> resumed_;
  std::optional<CheckpointWriter> checkpoints_;
  int resumed_round_ = -1;             // the rejection round a checkpoint resumed in
  std::vector<RejectionRound> rounds_; // rejection rounds done
  // Resumed after rejection rounds: what the point side was given, in the
  // problem as loaded (empty: the identity), and its observations.
  OriginalIndices origin_;
  // The order the solves walk the loaded points in (one process; over ranks
  // the shares handed out), taken at the load and handed to the point side.
  std::vector<int64_t> load_order_;
  GaugeReference gauge_;  // taken at the load (camera/gauge_hold.h)
  std::vector<int64_t> WalkOverSide();
  int64_t loaded_observations_ = 0;
  std::vector<double> loaded_pixels_;  // with rejection and a truth
  std::function<void(const OptimumView&)> analysis_;
  std::unique_ptr<PointSide> side_;  // main rank, from the solve to the finish
  DistributedPointSide* ranks_ = nullptr;  // side_, when it is spread over ranks
};

// What shapes a solve's result besides its input: the loss, the camera
// priors (as placed in the solve's frame) and their loss, the control
// points, the rejection criteria, and with `rigs` the rig geometry held
// (--rig-geometry fixed or fixed:IDS; refine adds nothing). A checkpoint
// written with another is refused (io/checkpoint.h).
SetupFingerprint SolveSetup(const SolveOptions& options, const Georeference& geo, bool rigs);

// The log line of one round of --reject-outliers.
std::string RejectionRoundLine(const RejectionCriteria& criteria, int r,
                               const RejectionRound& round);

// Refuses (std::runtime_error naming `input` and the first observations) a
// problem whose initial cost is not finite; returns how many observations
// are behind their cameras (from the same pass, ScanResiduals).
int64_t RefuseNonFiniteResiduals(const std::string& input, const Problem& problem,
                                 std::span<const int64_t> walk = {});

}  // namespace dba
