// Ranks and their traffic accounting over a transport; see communicator.h.
#include "dba/cluster/communicator.h"

#include <cstdio>
#include <cstdlib>

#include "dba/common/timer.h"

namespace dba {

// The MPI transport, when launched by MPI (mpi_transport.cc).
std::unique_ptr<Transport> MakeMpiTransport(int* argc, char*** argv);

const char* TrafficName(Traffic t) {
  switch (t) {
    case Traffic::kDistribution: return "distribution";
    case Traffic::kSubRcs: return "sub_rcs";
    case Traffic::kCameraUpdate: return "camera_update";
    case Traffic::kControl: return "control";
    case Traffic::kResult: return "result";
    case Traffic::kHalo: return "halo";
    case Traffic::kReduction: return "reduction";
  }
  return "unknown";
}

int64_t TrafficStats::total_bytes() const {
  int64_t s = 0;
  for (int64_t b : bytes) s += b;
  return s;
}

double TrafficStats::total_seconds() const {
  double s = 0;
  for (double x : seconds) s += x;
  return s;
}

double TrafficStats::total_wait_seconds() const {
  double s = 0;
  for (double x : wait_seconds) s += x;
  return s;
}

bool Communicator::LaunchedByMpi() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"}) {
    if (std::getenv(var) != nullptr) return true;
  }
  return false;
}

Communicator::Communicator(int* argc, char*** argv)
    : Communicator(LaunchedByMpi() ? MakeMpiTransport(argc, argv) : nullptr) {}

Communicator::Communicator(std::unique_ptr<Transport> transport) : transport_(std::move(transport)) {
  if (!transport_) return;
  rank_ = transport_->rank();
  size_ = transport_->size();
  ranks_on_node_ = transport_->ranks_on_node();
}

Communicator::~Communicator() = default;

void Communicator::SendBytes(int dest, Traffic t, const void* data, uint64_t bytes) {
  if (!transport_) return;
  Timer timer;
  transport_->Send(dest, data, bytes);
  stats_.bytes[static_cast<int>(t)] += static_cast<int64_t>(bytes);
  stats_.seconds[static_cast<int>(t)] += timer.Seconds();
}

void Communicator::RecvBytes(int source, Traffic t, void* data, uint64_t bytes) {
  if (!transport_) return;
  // Waiting until the message is there is not transfer time.
  Timer wait;
  transport_->WaitFor(source);
  stats_.wait_seconds[static_cast<int>(t)] += wait.Seconds();
  Timer timer;
  transport_->Recv(source, data, bytes);
  stats_.bytes[static_cast<int>(t)] += static_cast<int64_t>(bytes);
  stats_.seconds[static_cast<int>(t)] += timer.Seconds();
}

void Communicator::BroadcastBytes(Traffic t, void* data, uint64_t bytes) {
  if (!transport_) return;
  Timer timer;
  transport_->Broadcast(data, bytes);
  stats_.bytes[static_cast<int>(t)] += static_cast<int64_t>(bytes);
  // The other ranks mostly wait here for the main rank to decide.
  (rank_ == 0 ? stats_.seconds : stats_.wait_seconds)[static_cast<int>(t)] += timer.Seconds();
}

std::vector<double> Communicator::Gather(Traffic t, std::span<const double> local) {
  if (!transport_) return std::vector<double>(local.begin(), local.end());
  Timer timer;
  std::vector<double> all(rank_ == 0 ? local.size() * size_ : 0);
  transport_->Gather(local.data(), local.size(), all.data());
  stats_.bytes[static_cast<int>(t)] +=
      static_cast<int64_t>(local.size_bytes()) * (rank_ == 0 ? size_ : 1);
  // A few numbers per rank: the time is the wait for the slowest rank.
  stats_.wait_seconds[static_cast<int>(t)] += timer.Seconds();
  return all;
}

void Communicator::ExchangeBytes(Traffic t, const std::vector<ByteSpan>& send,
                                 const std::vector<ByteSpan>& recv) {
  if (!transport_) return;
  Timer timer;
  for (int r = 0; r < size_; ++r) {
    if (r == rank_) continue;
    if (r < static_cast<int>(recv.size())) stats_.bytes[static_cast<int>(t)] += recv[r].bytes;
    if (r < static_cast<int>(send.size())) stats_.bytes[static_cast<int>(t)] += send[r].bytes;
  }
  std::vector<ByteSpan> s(send), rv(recv);
  s.resize(size_);
  rv.resize(size_);
  s[rank_] = rv[rank_] = {};
  transport_->Exchange(s, rv);
  // Includes waiting for the peers to reach the exchange.
  stats_.seconds[static_cast<int>(t)] += timer.Seconds();
}

void Communicator::Allreduce(Traffic t, void* data, int64_t count, bool is_double, bool max) {
  if (!transport_ || count == 0) return;
  Timer timer;
  transport_->Allreduce(data, count, is_double, max);
  // Sent and received once each, as a ring or tree would per rank.
  stats_.bytes[static_cast<int>(t)] += 2 * count * 8;
  stats_.seconds[static_cast<int>(t)] += timer.Seconds();
}

void Communicator::AllreduceSum(Traffic t, std::span<double> values) {
  Allreduce(t, values.data(), static_cast<int64_t>(values.size()), true, false);
}

void Communicator::AllreduceMax(Traffic t, std::span<double> values) {
  Allreduce(t, values.data(), static_cast<int64_t>(values.size()), true, true);
}

void Communicator::AllreduceSum(Traffic t, std::span<int64_t> values) {
  Allreduce(t, values.data(), static_cast<int64_t>(values.size()), false, false);
}

void Communicator::AllreduceMax(Traffic t, std::span<int64_t> values) {
  Allreduce(t, values.data(), static_cast<int64_t>(values.size()), false, true);
}

void Communicator::Abort(const std::string& message, int status) const {
  std::fprintf(stderr, "dba: rank %d: error: %s\n", rank_, message.c_str());
  std::fflush(stderr);
  if (transport_) transport_->Abort(message, status);
  std::exit(status);
}

}  // namespace dba
