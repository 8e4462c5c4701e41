// The MPI transport (cluster/transport.h): the only file that talks MPI.
// Messages longer than 2^30 bytes are split into chunks of at most 2^30, so
// 64-bit sizes are safe with MPI's int counts (tests/mpi/large_message_check).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>

// The C bindings only (the C++ bindings are deprecated and need another library).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>

#include "dba/cluster/transport.h"

namespace dba {
namespace {

constexpr uint64_t kMaxChunkBytes = uint64_t{1} << 30;
constexpr int kTag = 7;

class MpiTransport : public Transport {
 public:
  MpiTransport(int* argc, char*** argv) {
    int provided = 0;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS) {
      std::fprintf(stderr, "dba: error: MPI_Init failed\n");
      std::exit(1);
    }
    // Errors inside MPI abort the job instead of hanging it.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_ARE_FATAL);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    MPI_Comm node;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
    MPI_Comm_size(node, &ranks_on_node_);
    MPI_Comm_free(&node);
  }
  ~MpiTransport() override { MPI_Finalize(); }

  int rank() const override { return rank_; }
  int size() const override { return size_; }
  int ranks_on_node() const override { return ranks_on_node_; }

  void Send(int dest, const void* data, uint64_t bytes) override {
    const char* p = static_cast<const char*>(data);
    do {
      const uint64_t n = std::min(bytes, kMaxChunkBytes);
      MPI_Send(p, static_cast<int>(n), MPI_BYTE, dest, kTag, MPI_COMM_WORLD);
      p += n;
      bytes -= n;
    } while (bytes > 0);
  }

  void WaitFor(int source) override {
    MPI_Probe(source, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  }

  void Recv(int source, void* data, uint64_t bytes) override {
    char* p = static_cast<char*>(data);
    do {
      const uint64_t n = std::min(bytes, kMaxChunkBytes);
      MPI_Recv(p, static_cast<int>(n), MPI_BYTE, source, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      p += n;
      bytes -= n;
    } while (bytes > 0);
  }

  void Broadcast(void* data, uint64_t bytes) override {
    char* p = static_cast<char*>(data);
    do {
      const uint64_t n = std::min(bytes, kMaxChunkBytes);
      MPI_Bcast(p, static_cast<int>(n), MPI_BYTE, 0, MPI_COMM_WORLD);
      p += n;
      bytes -= n;
    } while (bytes > 0);
  }

  void Gather(const double* local, uint64_t count, double* all) override {
    MPI_Gather(local, static_cast<int>(count), MPI_DOUBLE, all, static_cast<int>(count),
               MPI_DOUBLE, 0, MPI_COMM_WORLD);
  }

  void Exchange(const std::vector<Span>& send, const std::vector<Span>& recv) override {
    std::vector<MPI_Request> requests;
    auto post = [&](const Span& span, int peer, bool is_send) {
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
      }
    };
    for (int r = 0; r < size_; ++r) {
      if (r == rank_) continue;
      post(recv[r], r, false);
      post(send[r], r, true);
    }
    MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
  }

  void Allreduce(void* data, int64_t count, bool is_double, bool max) override {
    char* p = static_cast<char*>(data);
    const int64_t chunk = static_cast<int64_t>(kMaxChunkBytes / 8);
    for (int64_t done = 0; done < count; done += chunk) {
      const int n = static_cast<int>(std::min(chunk, count - done));
      MPI_Allreduce(MPI_IN_PLACE, p + done * 8, n, is_double ? MPI_DOUBLE : MPI_INT64_T,
                    max ? MPI_MAX : MPI_SUM, MPI_COMM_WORLD);
    }
  }

  [[noreturn]] void Abort(const std::string&, int status) override {
    MPI_Abort(MPI_COMM_WORLD, status);
    std::exit(status);
  }

 private:
  int rank_ = 0, size_ = 1, ranks_on_node_ = 1;
};

}  // namespace

std::unique_ptr<Transport> MakeMpiTransport(int* argc, char*** argv) {
  return std::make_unique<MpiTransport>(argc, argv);
}

}  // namespace dba
