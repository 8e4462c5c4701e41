// The MPI transport in one process (MPI's singleton start, no mpirun): one
// rank, and every operation on it as the semantics of transport.h say. The
// transport between processes (and messages beyond 2^30 bytes) is checked
// under mpirun: tests/mpi_solve.sh, tests/mpi/large_message_check.cc.
#include "dba/cluster/transport.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace dba {

std::unique_ptr<Transport> MakeMpiTransport(int* argc, char*** argv);

namespace {

TEST(MpiTransport, OneProcessIsRankZeroOfOneAndTalksToItself) {
  std::unique_ptr<Transport> t = MakeMpiTransport(nullptr, nullptr);
  EXPECT_EQ(t->rank(), 0);
  EXPECT_EQ(t->size(), 1);
  EXPECT_EQ(t->ranks_on_node(), 1);

  // A message to itself arrives whole, in order.
  const std::vector<double> sent = {1.5, -2.0, 3.25};
  t->Send(0, sent.data(), sizeof(double) * sent.size());
  const int64_t second = 42;
  t->Send(0, &second, sizeof second);
  t->WaitFor(0);
  std::vector<double> got(3);
  t->Recv(0, got.data(), sizeof(double) * got.size());
  int64_t got_second = 0;
  t->Recv(0, &got_second, sizeof got_second);
  EXPECT_EQ(got, sent);
  EXPECT_EQ(got_second, 42);

  // Collectives over one rank: the broadcast keeps, the gather copies, the
  // reductions return the rank's own values; an exchange with itself is no
  // message (the caller keeps its own part).
  std::vector<double> b = {7.0, 8.0};
  t->Broadcast(b.data(), sizeof(double) * b.size());
  EXPECT_EQ(b, (std::vector<double>{7.0, 8.0}));
  std::vector<double> all(2, 0.0);
  t->Gather(b.data(), 2, all.data());
  EXPECT_EQ(all, b);
  std::vector<double> sum = {1.0, 2.0};
  t->Allreduce(sum.data(), 2, true, false);
  EXPECT_EQ(sum, (std::vector<double>{1.0, 2.0}));
  int64_t top[2] = {-3, 9};
  t->Allreduce(top, 2, false, true);
  EXPECT_EQ(top[0], -3);
  EXPECT_EQ(top[1], 9);
  double mine = 5.0, theirs = 0.0;
  t->Exchange({{&mine, sizeof mine}}, {{&theirs, sizeof theirs}});
  EXPECT_EQ(theirs, 0.0);
}

}  // namespace
}  // namespace dba
