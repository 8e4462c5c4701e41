// MpiPointWorkers' protocol over ranks as threads: the global RCS summed on
// the main rank from the ranks' sub-RCSs is one process's RCS (1e-12), the
// points collected are the ranks', and the ranks end with their reports.
#include "dba/cluster/mpi_point_workers.h"

#include <gtest/gtest.h>

#include "dba/cluster/partition.h"
#include "dba/cluster/thread_transport.h"
#include "dba/lm/local_point_workers.h"
#include "dba/testing/dense_reference.h"
#include "dba/testing/synthetic_photo.h"

namespace dba {
namespace {

TEST(MpiPointWorkers, GatheredRcsIsOneProcesssRcs) {
  testing::SyntheticPhotoOptions o;
  o.geometry.num_cameras = 7;
  o.geometry.num_points = 90;
  o.geometry.pixel_noise = 0.5;
  o.geometry.point_perturbation = 0.05;
  const Problem full = testing::MakeSyntheticPhoto(o).problem;
  Problem whole = full;
  LocalPointWorkers one(&whole, DampingBounds{}, 1);
  const RcsSystem& reference = one.FormRcs(1e-3);
  const Eigen::MatrixXd S_ref = testing::DenseFromBsmc(reference.S);
  const std::vector<int32_t> group = PartitionPoints(full, 3, PartitionScheme::kCameraLocality);
  RunRanksAsThreads(3, [&](Communicator& comm) {
    RankShare share = ExtractShare(full, group, comm.rank());
    LocalPointWorkers workers(&share.problem, DampingBounds{}, 1);
    if (!comm.is_main()) {
      ShareRejection rejection;
      RunPointRank(&comm, &share, &workers, 0, &rejection);
      return;
    }
    Problem side = full;
    MpiPointWorkers mpi(&comm, UnknownLayout(side), &share, &workers);
    const RcsSystem& S = mpi.FormRcs(1e-3);
    const Eigen::MatrixXd dense = testing::DenseFromBsmc(S.S);
    ASSERT_EQ(dense.rows(), S_ref.rows());
    EXPECT_LE((dense - S_ref).cwiseAbs().maxCoeff(), 1e-12 * S_ref.cwiseAbs().maxCoeff());
    EXPECT_NEAR(S.cost, reference.cost, 1e-12 * reference.cost);
    std::vector<double> points(full.points.size(), -1.0);
    mpi.CollectPoints(&points);
    EXPECT_EQ(points, full.points);
    const std::vector<RankReport> reports = mpi.Finish(nullptr);
    int64_t observed = 0;
    for (const RankReport& r : reports) observed += r.observations;
    EXPECT_EQ(observed, full.num_observations());
  });
}

}  // namespace
}  // namespace dba
