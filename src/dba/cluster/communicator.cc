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

void Communicator::Abort(const std::string& message) const {
  std::fprintf(stderr, "dba: rank %d: error: %s\n", rank_, message.c_str());
  std::fflush(stderr);
  if (mpi_) MPI_Abort(MPI_COMM_WORLD, 1);
  std::exit(1);
}

}  // namespace dba
