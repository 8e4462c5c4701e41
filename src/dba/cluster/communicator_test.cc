// The ranks' exchanges over the in-process transport (N ranks as threads):
// what each operation delivers, in order, how it is counted, and that a
// failing rank ends the others instead of hanging them.
#include "dba/cluster/communicator.h"

#include <gtest/gtest.h>

#include <numeric>
#include <stdexcept>
#include <vector>

#include "dba/cluster/thread_transport.h"

namespace dba {
namespace {

TEST(Communicator, PointToPointInOrderAndCounted) {
  RunRanksAsThreads(3, [](Communicator& comm) {
    EXPECT_EQ(comm.size(), 3);
    if (comm.rank() == 0) {
      for (int r = 1; r < 3; ++r) {
        comm.SendVector(r, Traffic::kControl, std::vector<int64_t>{r, 10 * r});
        comm.SendVector(r, Traffic::kControl, std::vector<double>{0.5 * r});
      }
      EXPECT_EQ(comm.stats().bytes[static_cast<int>(Traffic::kControl)], 2 * (8 + 16 + 8 + 8));
    } else {
      EXPECT_EQ(comm.RecvVector<int64_t>(0, Traffic::kControl),
                (std::vector<int64_t>{comm.rank(), 10 * comm.rank()}));
      EXPECT_EQ(comm.RecvVector<double>(0, Traffic::kControl), std::vector<double>{0.5 * comm.rank()});
    }
  });
}

TEST(Communicator, CollectivesDeliverTheSameOnEveryRank) {
  RunRanksAsThreads(4, [](Communicator& comm) {
    int32_t decided = comm.is_main() ? 42 : 0;
    comm.Broadcast(Traffic::kControl, &decided);
    EXPECT_EQ(decided, 42);
    const std::vector<double> mine = {double(comm.rank()), 1.0};
    const std::vector<double> all = comm.Gather(Traffic::kControl, mine);
    if (comm.is_main()) {
      EXPECT_EQ(all, (std::vector<double>{0, 1, 1, 1, 2, 1, 3, 1}));
    } else {
      EXPECT_TRUE(all.empty());
    }
    std::vector<double> sum = {double(comm.rank()), 0.25};
    comm.AllreduceSum(Traffic::kReduction, sum);
    EXPECT_EQ(sum, (std::vector<double>{6.0, 1.0}));
    std::vector<int64_t> max = {comm.rank() * 7, -comm.rank()};
    comm.AllreduceMax(Traffic::kReduction, max);
    EXPECT_EQ(max, (std::vector<int64_t>{21, 0}));
  });
}

// Every rank sends rank q the values (me, q), q of them; empty spans are no
// message.
TEST(Communicator, ExchangeIsTheSparseAllToAll) {
  RunRanksAsThreads(3, [](Communicator& comm) {
    const int n = comm.size(), me = comm.rank();
    std::vector<std::vector<double>> out(n), in(n);
    std::vector<std::span<const double>> send(n);
    std::vector<std::span<double>> recv(n);
    for (int q = 0; q < n; ++q) {
      out[q].assign(q, 10.0 * me + q);
      in[q].assign(me, -1.0);
      send[q] = std::span<const double>(out[q]);
      recv[q] = std::span<double>(in[q]);
    }
    comm.Exchange(Traffic::kSubRcs, send, recv);
    for (int q = 0; q < n; ++q) {
      if (q == me) continue;
      EXPECT_EQ(in[q], std::vector<double>(me, 10.0 * q + me)) << me << " from " << q;
    }
  });
}

TEST(Communicator, AFailingRankEndsTheOthers) {
  EXPECT_THROW(RunRanksAsThreads(3,
                                 [](Communicator& comm) {
                                   if (comm.rank() == 2) throw std::runtime_error("rank 2 failed");
                                   int32_t x = 0;
                                   comm.Broadcast(Traffic::kControl, &x);  // 2 never comes
                                   std::vector<double> v(1, 1.0);
                                   comm.AllreduceSum(Traffic::kReduction, v);
                                 }),
               std::runtime_error);
}

}  // namespace
}  // namespace dba
