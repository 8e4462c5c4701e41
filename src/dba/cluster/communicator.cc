// MPI transport with traffic accounting; see communicator.h.
#include "dba/cluster/communicator.h"

// The C bindings only (the C++ bindings are deprecated and need another library).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "dba/common/timer.h"

namespace dba {
namespace {

constexpr uint64_t kMaxChunkBytes = uint64_t{1} << 30;
constexpr int kTag = 7;

}  // namespace

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

Communicator::Communicator(int* argc, char*** argv) {
  if (!LaunchedByMpi()) return;
  int provided = 0;
  if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
    std::fprintf(stderr, "dba: error: MPI_Init failed\n");
    std::exit(1);
  }
  mpi_ = true;
  // Errors inside MPI abort the job instead of hanging it.
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_ARE_FATAL);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
  MPI_Comm_size(node, &ranks_on_node_);
  MPI_Comm_free(&node);
}

Communicator::~Communicator() {
  if (mpi_) MPI_Finalize();
}

void Communicator::SendBytes(int dest, Traffic t, const void* data, uint64_t bytes) {
  Timer timer;
  const char* p = static_cast<const char*>(data);
  do {
    const uint64_t n = std::min(bytes, kMaxChunkBytes);
    MPI_Send(p, static_cast<int>(n), MPI_BYTE, dest, kTag, MPI_COMM_WORLD);
    p += n;
    bytes -= n;
    stats_.bytes[static_cast<int>(t)] += static_cast<int64_t>(n);
  } while (bytes > 0);
  stats_.seconds[static_cast<int>(t)] += timer.Seconds();
}

void Communicator::RecvBytes(int source, Traffic t, void* data, uint64_t bytes) {
  // Waiting until the message is there is not transfer time.
  Timer wait;
  MPI_Probe(source, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  stats_.wait_seconds[static_cast<int>(t)] += wait.Seconds();
  Timer timer;
  char* p = static_cast<char*>(data);
  do {
    const uint64_t n = std::min(bytes, kMaxChunkBytes);
    MPI_Recv(p, static_cast<int>(n), MPI_BYTE, source, kTag, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    p += n;
    bytes -= n;
    stats_.bytes[static_cast<int>(t)] += static_cast<int64_t>(n);
  } while (bytes > 0);
  stats_.seconds[static_cast<int>(t)] += timer.Seconds();
}

void Communicator::BroadcastBytes(Traffic t, void* data, uint64_t bytes) {
  if (!mpi_) return;
  Timer timer;
  char* p = static_cast<char*>(data);
  do {
    const uint64_t n = std::min(bytes, kMaxChunkBytes);
    MPI_Bcast(p, static_cast<int>(n), MPI_BYTE, 0, MPI_COMM_WORLD);
    p += n;
    bytes -= n;
    stats_.bytes[static_cast<int>(t)] += static_cast<int64_t>(n);
  } while (bytes > 0);
  // The other ranks mostly wait here for the main rank to decide.
  (rank_ == 0 ? stats_.seconds : stats_.wait_seconds)[static_cast<int>(t)] += timer.Seconds();
}

std::vector<double> Communicator::Gather(Traffic t, std::span<const double> local) {
  if (!mpi_) return std::vector<double>(local.begin(), local.end());
  Timer timer;
  std::vector<double> all(rank_ == 0 ? local.size() * size_ : 0);
  MPI_Gather(local.data(), static_cast<int>(local.size()), MPI_DOUBLE, all.data(),
             static_cast<int>(local.size()), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  stats_.bytes[static_cast<int>(t)] +=
      static_cast<int64_t>(local.size_bytes()) * (rank_ == 0 ? size_ : 1);
  // A few numbers per rank: the time is the wait for the slowest rank.
  stats_.wait_seconds[static_cast<int>(t)] += timer.Seconds();
  return all;
}

void Communicator::ExchangeBytes(Traffic t, const std::vector<ByteSpan>& send,
                                 const std::vector<ByteSpan>& recv) {
  if (!mpi_) return;
  Timer timer;
  std::vector<MPI_Request> requests;
  auto post = [&](const ByteSpan& span, int peer, bool is_send) {
    char* p = static_cast<char*>(span.data);
    for (uint64_t left = span.bytes; left > 0;) {
      const uint64_t n = std::min(left, kMaxChunkBytes);
      requests.emplace_back();
      if (is_send) {
        MPI_Isend(p, static_cast<int>(n), MPI_BYTE, peer, kTag + 1, MPI_COMM_WORLD, &requests.back());
      } else {
        MPI_Irecv(p, static_cast<int>(n), MPI_BYTE, peer, kTag + 1, MPI_COMM_WORLD, &requests.back());
      }
      p += n;
      left -= n;
      stats_.bytes[static_cast<int>(t)] += static_cast<int64_t>(n);
    }
  };
  for (int r = 0; r < size_; ++r) {
    if (r == rank_) continue;
    if (r < static_cast<int>(recv.size())) post(recv[r], r, false);
    if (r < static_cast<int>(send.size())) post(send[r], r, true);
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  // Includes waiting for the peers to reach the exchange.
  stats_.seconds[static_cast<int>(t)] += timer.Seconds();
}

void Communicator::Allreduce(Traffic t, void* data, int64_t count, bool is_double, bool max) {
  if (!mpi_ || count == 0) return;
  Timer timer;
  constexpr int64_t bytes_each = 8;  // double or int64
  char* p = static_cast<char*>(data);
  const int64_t chunk = static_cast<int64_t>(kMaxChunkBytes / 8);
  for (int64_t done = 0; done < count; done += chunk) {
    const int n = static_cast<int>(std::min(chunk, count - done));
    MPI_Allreduce(MPI_IN_PLACE, p + done * bytes_each, n, is_double ? MPI_DOUBLE : MPI_INT64_T,
                  max ? MPI_MAX : MPI_SUM, MPI_COMM_WORLD);
  }
  // Sent and received once each, as a ring or tree would per rank.
  stats_.bytes[static_cast<int>(t)] += 2 * count * bytes_each;
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
  if (mpi_) MPI_Abort(MPI_COMM_WORLD, status);
  std::exit(status);
}

}  // namespace dba
