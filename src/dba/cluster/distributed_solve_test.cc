// The distributed solve in one test binary (ranks as threads: no mpirun):
// N ranks reach one process's optimum (1e-9 with an exact solve), with the
// RCS gathered on rank 0 and spread over the ranks, from a whole problem
// handed out and from a .dba each rank reads itself; the ranks' outlier
// rejection leaves what one process's does. This drives every file of
// cluster/: the partition, the shares, the sub-RCS aggregation, the RCS
// spread over the ranks and its planning, MpiPointWorkers' protocol.
#include "dba/cluster/distributed_solve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <mutex>

#include "dba/cluster/thread_transport.h"
#include "dba/common/fault_seam.h"
#include "dba/io/binary_problem.h"
#include "dba/problem/point_order.h"
#include "dba/problem/random_renumbering.h"
#include "dba/camera/pose_similarity.h"
#include "dba/lm/bundle_adjust.h"
#include "dba/lm/solve_with_priors.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/scattered_survey.h"
#include "dba/testing/synthetic_bal.h"
#include "dba/testing/synthetic_photo.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

Problem Survey(bool photo) {
  testing::SyntheticBalOptions g;
  g.num_cameras = 9;
  g.num_points = 150;
  g.pixel_noise = 0.5;
  g.rotation_perturbation = 1e-3;
  g.point_perturbation = 0.05;
  if (!photo) return testing::MakeSyntheticBal(g).problem;
  testing::SyntheticPhotoOptions o;
  o.geometry = g;
  o.focal_perturbation = 1e-3;
  return testing::MakeSyntheticPhoto(o).problem;
}

LmOptions Exact(LinearSolverType type) {
  LmOptions o;
  o.num_threads = 1;
  o.linear_solver.type = type;
  o.linear_solver.pcg.eta = 0;
  o.linear_solver.pcg.relative_tolerance = 1e-14;
  o.linear_solver.pcg.max_iterations = 2000;
  o.function_tolerance = 1e-12;
  return o;
}

struct RanksRun {
  double final_cost = 0;
  Vec3 lever_arm = Vec3::Zero();
  std::vector<double> cameras, points;
  Eigen::MatrixXd S;  // at the optimum, with priors (AtOptimum)
  SolveOnRanksSummary summary;
  KeptObservations kept;
  int pcg_iterations = 0;
};

// `problem` (or `binary` read by every rank) solved on `ranks` threads;
// `reject` > 0: one rejection round and a second solve.
RanksRun SolveOnRanks(int ranks, const Problem& problem, const std::string& binary,
                      const LmOptions& o, DistributedOptions d, double reject = 0,
                      const CameraPriors& priors = {}) {
  RanksRun run;
  RunRanksAsThreads(ranks, [&](Communicator& comm) {
    if (!comm.is_main()) {
      ServePoints(&comm, o, d, binary);
      return;
    }
    Problem p = binary.empty() ? problem : Problem(ReadBinaryCameraSide(binary));
    DistributedPointSide side(&comm, o, d, binary, &p);
    BundleAdjustSummary s = side.Solve(o, priors, {});
    if (reject > 0) {
      PoseObservations poses;
      side.DropOutliers({reject, 0.0}, 1, true, &poses);
      CameraPriors next = priors;  // from where the first solve left the lever arm
      next.lever_arm = s.lever_arm;
      s = side.Solve(o, next, {});
      run.kept = side.Kept();
    }
    if (!priors.empty()) {
      CameraPriors at = priors;
      at.lever_arm = s.lever_arm;
      side.AtOptimum(o, at, [&](const RcsSystem& r) { run.S = testing::DenseFromBsmc(r.S); });
    }
    side.Finish(true, &run.summary);
    run.final_cost = s.lm.final_cost;
    run.pcg_iterations = s.lm.total_linear_iterations;
    run.lever_arm = s.lever_arm;
    run.cameras = p.cameras;
    run.points = p.points;
  });
  return run;
}

void ExpectSame(const std::vector<double>& a, const std::vector<double>& b, double rel) {
  ASSERT_EQ(a.size(), b.size());
  double scale = 1, diff = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    scale = std::max(scale, std::abs(b[i]));
    diff = std::max(diff, std::abs(a[i] - b[i]));
  }
  EXPECT_LE(diff, rel * scale);
}

TEST(DistributedSolve, RanksReachOneProcessGathered) {
  for (bool photo : {false, true}) {
    const Problem p = Survey(photo);
    const LmOptions o = Exact(LinearSolverType::kDense);
    Problem one = p;
    const double cost = BundleAdjust(o, &one).lm.final_cost;
    for (int ranks : {2, 3}) {
      DistributedOptions d;
      d.rcs = DistributedOptions::Rcs::kGather;
      const RanksRun run = SolveOnRanks(ranks, p, "", o, d);
      EXPECT_NEAR(run.final_cost, cost, 1e-9 * cost) << ranks << " ranks, photo " << photo;
      EXPECT_EQ(run.summary.ranks, ranks);
      EXPECT_EQ(run.summary.rank_reports.size(), static_cast<size_t>(ranks));
    }
  }
}

TEST(DistributedSolve, RcsSpreadOverRanksReachesOneProcess) {
  const Problem p = Survey(true);
  const LmOptions o = Exact(LinearSolverType::kPcg);
  Problem one = p;
  const double cost = BundleAdjust(Exact(LinearSolverType::kDense), &one).lm.final_cost;
  DistributedOptions d;
  d.rcs = DistributedOptions::Rcs::kDistributed;
  d.main_role = DistributedOptions::MainRole::kForms;
  const RanksRun run = SolveOnRanks(3, p, "", o, d);
  EXPECT_NEAR(run.final_cost, cost, 1e-9 * cost);
  EXPECT_EQ(run.summary.rcs, RcsPlacement::kDistributed);
  // Every global row has one owner: the owners' rows add up to them all.
  int64_t owned = 0;
  for (const RankReport& r : run.summary.rank_reports) owned += r.owned_rows;
  EXPECT_EQ(owned, UnknownLayout(p).num_block_rows());
}

TEST(DistributedSolve, RanksReadingADbaReachTheHandedOutSolve) {
  const Problem p = Survey(true);
  const std::string path = testing::TempPath("ranks_read.dba");
  WriteBinaryProblem(p, path);
  const LmOptions o = Exact(LinearSolverType::kDense);
  DistributedOptions d;
  d.rcs = DistributedOptions::Rcs::kGather;
  const RanksRun handed = SolveOnRanks(3, p, "", o, d);
  const RanksRun read = SolveOnRanks(3, p, path, o, d);
  EXPECT_NEAR(read.final_cost, handed.final_cost, 1e-12 * handed.final_cost);
  ExpectSame(read.cameras, handed.cameras, 1e-12);
  ExpectSame(read.points, handed.points, 1e-12);
}

TEST(DistributedSolve, RanksRejectWhatOneProcessRejects) {
  Problem p = Survey(false);
  for (int o = 0; o < p.num_observations(); o += 37) p.obs_pixel[2 * o] += 40.0;  // mismatches
  const LmOptions o = Exact(LinearSolverType::kDense);
  Problem one = p;
  BundleAdjust(o, &one);
  OriginalIndices original = OriginalIndices::Identity(one);
  const RejectionRound round = DropOutliers({3.0, 0.0}, 1, &one, &original);
  ASSERT_GT(round.observations_dropped, 0);
  const double cost = BundleAdjust(o, &one).lm.final_cost;
  DistributedOptions d;
  d.rcs = DistributedOptions::Rcs::kGather;
  const RanksRun run = SolveOnRanks(3, p, "", o, d, 3.0);
  EXPECT_NEAR(run.final_cost, cost, 1e-9 * cost);
  const KeptObservations kept = KeptFlags(original, p.num_observations(), p.num_points());
  EXPECT_EQ(run.kept.observation, kept.observation);
  EXPECT_EQ(run.kept.point, kept.point);
}

// GNSS priors on every image but the last, at antennas 0.4, -0.3, 0.8 from
// the true centres (σ 1 cm), the lever arm refined from zero: its 3
// unknowns are the last row of the gathered RCS, met by every camera row
// (cluster/aggregate_sub_rcs.h), and the ranks end where one process ends.
TEST(DistributedSolve, ARefinedLeverArmOnRanksEndsWhereOneProcessEnds) {
  testing::SyntheticPhotoOptions g;
  g.geometry.num_cameras = 9;
  g.geometry.num_points = 150;
  g.geometry.pixel_noise = 0.5;
  g.geometry.rotation_perturbation = 1e-3;
  g.geometry.point_perturbation = 0.05;
  g.focal_perturbation = 1e-3;
  const testing::SyntheticProblem s = testing::MakeSyntheticPhoto(g);
  CameraPriors priors;
  const Vec3 truth(0.4, -0.3, 0.8);
  for (int32_t i = 0; i + 1 < s.truth.num_images(); ++i) {
    priors.priors.push_back({i, AntennaPosition(s.truth.camera(i), truth), Vec3(0.01, 0.01, 0.01)});
  }
  priors.refine_lever_arm = true;
  const LmOptions o = Exact(LinearSolverType::kDense);
  Problem one = s.problem;
  const BundleAdjustSummary single = BundleAdjust(o, &one, {}, {}, &priors);
  ASSERT_GT(single.lever_arm.norm(), 0.1);  // it moved from 0
  // The RCS at the optimum (the analysis of a solve): its last row the
  // lever arm's.
  CameraPriors at = priors;
  at.lever_arm = single.lever_arm;
  LocalPointWorkers workers(&one, o.damping, 1, o.loss, {}, false, true);
  Eigen::MatrixXd S;
  FormAtCurrentParameters(one, &workers, &at, [&](const RcsSystem& r) {
    S = testing::DenseFromBsmc(r.S);
    EXPECT_EQ(r.layout.lever_arm_row(), r.layout.num_block_rows() - 1);
  });
  ASSERT_GT(S.bottomLeftCorner(3, S.cols() - 3).cwiseAbs().maxCoeff(), 0.0);
  DistributedOptions d;
  d.lever_arm_row = true;  // auto: gathered
  for (int ranks : {2, 3}) {
    const RanksRun run = SolveOnRanks(ranks, s.problem, "", o, d, 0, priors);
    EXPECT_EQ(run.summary.rcs, RcsPlacement::kGather);
    EXPECT_NEAR(run.final_cost, single.lm.final_cost, 1e-9 * single.lm.final_cost) << ranks;
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(run.lever_arm[k], single.lever_arm[k], 1e-9 * single.lever_arm.norm()) << ranks;
    }
    ExpectSame(run.cameras, one.cameras, 1e-8);
    ASSERT_EQ(run.S.rows(), S.rows());
    EXPECT_LE((run.S - S).cwiseAbs().maxCoeff(), 1e-7 * S.cwiseAbs().maxCoeff()) << ranks;
  }
  // A rejection round between two solves: the ranks' workers are made again
  // with the lever arm's row, and end where one process ends.
  Problem cut = s.problem;
  for (int64_t k = 0; k < cut.num_observations(); k += 41) cut.obs_pixel[2 * k] += 40.0;
  Problem cut_one = cut;
  const BundleAdjustSummary first = BundleAdjust(o, &cut_one, {}, {}, &priors);
  OriginalIndices original = OriginalIndices::Identity(cut_one);
  ASSERT_GT(DropOutliers({3.0, 0.0}, 1, &cut_one, &original).observations_dropped, 0);
  CameraPriors next = priors;
  next.lever_arm = first.lever_arm;
  const BundleAdjustSummary second = BundleAdjust(o, &cut_one, {}, {}, &next);
  const RanksRun cut_run = SolveOnRanks(2, cut, "", o, d, 3.0, priors);
  EXPECT_NEAR(cut_run.final_cost, second.lm.final_cost, 1e-9 * second.lm.final_cost);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(cut_run.lever_arm[k], second.lever_arm[k], 1e-9 * second.lever_arm.norm());
  }
  // Auto with PCG gathers too; asked to spread the RCS, it is refused by name.
  EXPECT_EQ(ChooseRcsPlacement(d, Exact(LinearSolverType::kPcg), 3), RcsPlacement::kGather);
  d.rcs = DistributedOptions::Rcs::kDistributed;
  EXPECT_THROW(ChooseRcsPlacement(d, Exact(LinearSolverType::kPcg), 3), std::invalid_argument);
}

// A rank that fails at a point of the protocol (common/fault_seam.h) ends
// the solve on every rank with its error, at each point where it can.
void FailRankTwoAtFirst(int rank, const char* step, int count) {
  static std::mutex m;
  std::lock_guard<std::mutex> lock(m);
  static std::string wanted;
  if (rank < 0) {  // set the point
    wanted = step;
    return;
  }
  if (rank == 2 && count == 1 && wanted == step) {
    throw std::runtime_error(std::string("rank 2 failed at ") + step);
  }
}

TEST(DistributedSolve, ARankFailingAtAnyProtocolPointEndsTheSolveWithItsError) {
  const Problem p = Survey(true);
  const LmOptions o = Exact(LinearSolverType::kDense);
  DistributedOptions d;
  d.rcs = DistributedOptions::Rcs::kGather;
  SetFaultHook(FailRankTwoAtFirst);
  for (const char* step : {"form", "step", "finish", "end"}) {
    FailRankTwoAtFirst(-1, step, 0);
    try {
      SolveOnRanks(3, p, "", o, d);
      ADD_FAILURE() << step << ": no error";
    } catch (const std::exception& e) {
      EXPECT_EQ(std::string(e.what()), std::string("rank 2 failed at ") + step);
    }
  }
  SetFaultHook(nullptr);
  EXPECT_GT(SolveOnRanks(3, p, "", o, d).final_cost, 0.0);  // no hook: no fault
}

// A survey whose points come in a random order: every rank walks its share
// (cluster/rank_share.h's WalkShare), read from a .dba or handed out, and the
// ranks end where one process ends.
// Its shares' cameras are numbered by their walks, so blocks of a sub-RCS
// land transposed in the global RCS, gathered or spread over the ranks.
TEST(DistributedSolve, ScatteredInputsAreWalkedOnEveryRankAndEndWhereOneProcessEnds) {
  Problem p = testing::MakeScatteredSurvey("scattered_gen.dba", 30, 100, 9, 4).scattered;
  RenumberAtRandom(5, &p);  // the cameras too
  ASSERT_FALSE(PointWalk(p).empty());
  const std::string path = testing::TempPath("scattered.dba");
  WriteBinaryProblem(p, path);
  const LmOptions o = Exact(LinearSolverType::kDense);
  Problem one = p;
  const double cost = BundleAdjust(o, &one).lm.final_cost;
  for (auto rcs : {DistributedOptions::Rcs::kGather, DistributedOptions::Rcs::kDistributed}) {
    DistributedOptions d;
    d.rcs = rcs;
    LmOptions on_ranks = o;
    if (rcs == DistributedOptions::Rcs::kDistributed) {
      on_ranks = Exact(LinearSolverType::kPcg);
      on_ranks.linear_solver.pcg.relative_tolerance = 1e-12;
    }
    for (const std::string& binary : {std::string(), path}) {
      const RanksRun run = SolveOnRanks(3, p, binary, on_ranks, d);
      const std::string what = std::string(binary.empty() ? "handed out" : "read") +
                               (rcs == DistributedOptions::Rcs::kGather ? ", gathered" : ", spread");
      EXPECT_NEAR(run.final_cost, cost, 1e-9 * cost) << what;
      ExpectSame(run.cameras, one.cameras, 1e-8);  // in the input's numbering
      ExpectSame(run.points, one.points, 1e-8);
    }
  }
}

// The RCS spread over 4 ranks and solved by PCG with the default options:
// the same survey in the generator's order and with its cameras and points
// renumbered at random takes about as many PCG iterations (the owners'
// ranges and the two-level aggregates follow the cameras' places, not their
// numbers; in row order the renumbered one took 411 against 257).
TEST(DistributedSolve, PcgOnFourRanksTakesAsManyIterationsWhateverTheNumbering) {
  const Problem spatial = testing::MakeScatteredSurvey("numbering.dba", 300, 300, 3, 1).spatial;
  Problem shuffled = spatial;
  RenumberAtRandom(7, &shuffled);
  LmOptions o;
  o.num_threads = 1;
  DistributedOptions d;
  d.rcs = DistributedOptions::Rcs::kDistributed;
  const RanksRun a = SolveOnRanks(4, spatial, "", o, d);
  const RanksRun b = SolveOnRanks(4, shuffled, "", o, d);
  ASSERT_GT(a.pcg_iterations, 0);
  EXPECT_LE(std::abs(a.pcg_iterations - b.pcg_iterations), 0.1 * a.pcg_iterations)
      << a.pcg_iterations << " against " << b.pcg_iterations;
  EXPECT_NEAR(b.final_cost, a.final_cost, 1e-5 * a.final_cost);
}

}  // namespace
}  // namespace dba
