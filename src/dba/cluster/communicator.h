// The ranks of a solve and what they exchange (docs/design.md §4). Ranks
// exchange typed arrays; every transfer is counted, in bytes and seconds, under
// a traffic category, so the communication cost of a solve is measured (paper
// Table 5). The bytes move by a transport (cluster/transport.h): MPI between
// processes (the only code that talks MPI: mpi_transport.cc, which splits
// messages past 2^30 bytes, tests/mpi/large_message_check), or threads of one
// process for tests (thread_transport.h).
//
// Thread safety: call from one thread per rank (MPI_THREAD_FUNNELED).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "dba/cluster/transport.h"

namespace dba {

// kSubRcs: sub-RCSs to the main rank (gather) or to the owners of their rows
// (reduce-scatter); kHalo: PCG's halo exchanges and their transposed returns;
// kReduction: PCG's all-reduces and the coarse solve's gather and scatter.
enum class Traffic {
  kDistribution, kSubRcs, kCameraUpdate, kControl, kResult, kHalo, kReduction
};
inline constexpr int kNumTraffic = 7;
const char* TrafficName(Traffic t);

struct TrafficStats {
  int64_t bytes[kNumTraffic] = {};  // sent plus received by this rank
  double seconds[kNumTraffic] = {};  // wall time moving data (waits excluded)
  // Wall time a receive spent waiting for the sender to be ready (the other
  // rank still computing): load imbalance, not communication cost.
  double wait_seconds[kNumTraffic] = {};
  int64_t total_bytes() const;
  double total_seconds() const;
  double total_wait_seconds() const;
};

class Communicator {
 public:
  // True when this process was started by an MPI launcher (mpirun, srun).
  static bool LaunchedByMpi();
  // Initializes MPI when launched by MPI; otherwise a single rank without
  // MPI. Aborts the job on failure.
  Communicator(int* argc, char*** argv);
  // A single rank without MPI, even under an MPI launcher (a library caller,
  // e.g. the Python module, that solves in its own process).
  struct SingleRank {};
  explicit Communicator(SingleRank) {}
  // A rank over a transport of its own (the in-process one of tests).
  explicit Communicator(std::unique_ptr<Transport> transport);
  ~Communicator();
  // Ends the transport now (MPI_Finalize, collective: every rank calls it);
  // nothing is exchanged after. The destructor does it otherwise.
  void End() { transport_.reset(); }
  Communicator(const Communicator&) = delete;
  Communicator& operator=(const Communicator&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool is_main() const { return rank_ == 0; }
  // Ranks on this node (shared memory), for the threads-per-rank default.
  int ranks_on_node() const { return ranks_on_node_; }

  template <typename T>
  void Send(int dest, Traffic t, std::span<const T> data) {
    SendBytes(dest, t, data.data(), data.size_bytes());
  }
  template <typename T>
  void Recv(int source, Traffic t, std::span<T> data) {
    RecvBytes(source, t, data.data(), data.size_bytes());
  }
  // A vector with its length in front.
  template <typename T>
  void SendVector(int dest, Traffic t, const std::vector<T>& v) {
    const uint64_t n = v.size();
    SendBytes(dest, t, &n, sizeof n);
    SendBytes(dest, t, v.data(), n * sizeof(T));
  }
  template <typename T>
  std::vector<T> RecvVector(int source, Traffic t) {
    uint64_t n = 0;
    RecvBytes(source, t, &n, sizeof n);
    std::vector<T> v(n);
    RecvBytes(source, t, v.data(), n * sizeof(T));
    return v;
  }
  // Broadcast from rank 0.
  template <typename T>
  void Broadcast(Traffic t, std::span<T> data) {
    BroadcastBytes(t, data.data(), data.size_bytes());
  }
  template <typename T>
  void Broadcast(Traffic t, T* value) {
    BroadcastBytes(t, value, sizeof(T));
  }
  // Gathers `count` doubles from every rank at rank 0, in rank order.
  std::vector<double> Gather(Traffic t, std::span<const double> local);

  // Every rank sends send[r] to rank r and receives recv[r] from rank r, all
  // at once (non-blocking, chunked past 2^30 bytes); sizes agreed before (an
  // empty span: nothing to or from that rank; a rank's own entry is
  // ignored). The sparse all-to-all of the distributed RCS.
  template <typename T>
  void Exchange(Traffic t, const std::vector<std::span<const T>>& send,
                const std::vector<std::span<T>>& recv) {
    std::vector<ByteSpan> s(send.size()), r(recv.size());
    for (size_t i = 0; i < send.size(); ++i) s[i] = {(void*)send[i].data(), send[i].size_bytes()};
    for (size_t i = 0; i < recv.size(); ++i) r[i] = {recv[i].data(), recv[i].size_bytes()};
    ExchangeBytes(t, s, r);
  }
  // In place: every rank's `values` summed elementwise (or maxed) over all
  // ranks, the same sum on every rank.
  void AllreduceSum(Traffic t, std::span<double> values);
  void AllreduceMax(Traffic t, std::span<double> values);
  // In place: int64 counts summed (maxed) over all ranks.
  void AllreduceSum(Traffic t, std::span<int64_t> values);
  void AllreduceMax(Traffic t, std::span<int64_t> values);

  // Ends the whole job: prints "dba: rank R: error: MESSAGE" and aborts every
  // rank with `status` (mpirun exits with it: 2 for arguments, 1 otherwise).
  // Never returns.
  [[noreturn]] void Abort(const std::string& message, int status = 1) const;

  const TrafficStats& stats() const { return stats_; }

 private:
  void SendBytes(int dest, Traffic t, const void* data, uint64_t bytes);
  void RecvBytes(int source, Traffic t, void* data, uint64_t bytes);
  void BroadcastBytes(Traffic t, void* data, uint64_t bytes);
  using ByteSpan = Transport::Span;
  void ExchangeBytes(Traffic t, const std::vector<ByteSpan>& send,
                     const std::vector<ByteSpan>& recv);
  void Allreduce(Traffic t, void* data, int64_t count, bool is_double, bool max);

  std::unique_ptr<Transport> transport_;  // none: a single rank
  int rank_ = 0;
  int size_ = 1;
  int ranks_on_node_ = 1;
  TrafficStats stats_;
};

}  // namespace dba
