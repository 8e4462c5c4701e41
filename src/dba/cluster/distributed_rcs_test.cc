// The RCS spread over ranks as threads: every rank's sub-RCS reduced to its
// rows' owners, the damped system solved by PCG across the ranks (block-
// Jacobi and two-level), δc spread back: the main rank's δc is the dense
// solution of one process's damped RCS (1e-9, a tight solve).
#include "dba/cluster/distributed_rcs.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "dba/cluster/partition.h"
#include "dba/cluster/rank_share.h"
#include "dba/cluster/thread_transport.h"
#include "dba/lm/local_point_workers.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

// S δ = b of one process's RCS at λ, damped as the solvers damp it.
Eigen::VectorXd DenseStep(const Problem& problem, double lambda) {
  Problem p = problem;
  LocalPointWorkers one(&p, DampingBounds{}, 1);
  RcsSystem& sys = one.FormRcs(lambda);
  DampCameraBlocks(lambda, DampingBounds{}, sys.camera_side_jtj_diagonal, &sys.S);
  const Eigen::MatrixXd S = testing::DenseFromBsmc(sys.S);
  return testing::SolveSymmetric(S, Eigen::Map<const Eigen::VectorXd>(sys.b.data(), S.rows()));
}

void SolveSpread(PreconditionerType preconditioner, int ranks = 3) {
  testing::SyntheticPhotoOptions o;
  o.geometry.num_cameras = 8;
  o.geometry.num_points = 120;
  o.geometry.pixel_noise = 0.5;
  o.geometry.point_perturbation = 0.05;
  const Problem full = testing::MakeSyntheticPhoto(o).problem;
  const double lambda = 1e-2;
  const Eigen::VectorXd want = DenseStep(full, lambda);
  const UnknownLayout global(full);
  const std::vector<int32_t> group = PartitionPoints(full, ranks, PartitionScheme::kCameraLocality);
  RunRanksAsThreads(ranks, [&](Communicator& comm) {
    RankShare share = ExtractShare(full, group, comm.rank());
    LocalPointWorkers workers(&share.problem, DampingBounds{}, 1);
    RcsSystem& sub = workers.FormRcs(lambda);
    const std::vector<int32_t> rows = global.RowsOfEntities(
        sub.layout.RowEntities(share.global_camera, share.global_intrinsics));
    LinearSolverOptions linear;
    linear.num_threads = 1;
    linear.preconditioner = preconditioner;
    linear.coarse_basis = CoarseBasis::kParameters;
    linear.pcg.eta = 0;
    linear.pcg.relative_tolerance = 1e-13;
    linear.pcg.max_iterations = 1000;
    DistributedRcs rcs(&comm, global.block_sizes(), &sub.S, rows, linear);
    rcs.Reduce(&sub);
    const LinearSolveSummary solve = rcs.Solve(lambda, DampingBounds{});
    EXPECT_TRUE(solve.ok);
    std::vector<double> delta;
    rcs.SpreadStep(nullptr, &delta);
    if (!comm.is_main()) return;
    ASSERT_EQ(static_cast<int64_t>(delta.size()), want.size());
    const Eigen::Map<const Eigen::VectorXd> got(delta.data(), want.size());
    EXPECT_LE((got - want).norm(), 1e-9 * want.norm()) << ranks << " ranks";
  });
}

TEST(DistributedRcs, PcgAcrossRanksIsTheDenseStepBlockJacobi) {
  SolveSpread(PreconditionerType::kBlockJacobi);
}

TEST(DistributedRcs, OneAndTwoRanksAreTheDenseStep) {
  SolveSpread(PreconditionerType::kBlockJacobi, 1);
  SolveSpread(PreconditionerType::kBlockJacobi, 2);
}

TEST(DistributedRcs, PcgAcrossRanksIsTheDenseStepTwoLevel) {
  SolveSpread(PreconditionerType::kTwoLevel);
}

}  // namespace
}  // namespace dba
