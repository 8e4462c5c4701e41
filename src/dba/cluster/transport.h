// How ranks move bytes, under Communicator (which counts the traffic): MPI
// between processes (mpi_transport.cc, the only file that includes mpi.h),
// or threads of one process (thread_transport.h), so that the distributed
// code runs and is tested in one test binary without mpirun.
//
// Semantics, the same for both: point-to-point messages from one rank to
// another arrive in order; a broadcast, gather, exchange or reduction is
// collective (every rank calls it, in the same order); a zero-length part
// of an exchange is no message.
//
// Thread safety: one caller per rank.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace dba {

class Transport {
 public:
  struct Span {
    void* data = nullptr;
    uint64_t bytes = 0;
  };
  virtual ~Transport() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  virtual int ranks_on_node() const = 0;
  virtual void Send(int dest, const void* data, uint64_t bytes) = 0;
  // Blocks until a message from `source` is there (its wait is not transfer
  // time), then Recv takes it (exactly `bytes`).
  virtual void WaitFor(int source) = 0;
  virtual void Recv(int source, void* data, uint64_t bytes) = 0;
  virtual void Broadcast(void* data, uint64_t bytes) = 0;  // from rank 0
  // `count` doubles from every rank into `all` on rank 0, in rank order.
  virtual void Gather(const double* local, uint64_t count, double* all) = 0;
  // send[r] to rank r and recv[r] from it, all at once.
  virtual void Exchange(const std::vector<Span>& send, const std::vector<Span>& recv) = 0;
  // In place, every rank's values summed (or maxed), the same on every rank.
  virtual void Allreduce(void* data, int64_t count, bool is_double, bool max) = 0;
  // Ends every rank with `status` (after `message` is printed by the caller).
  [[noreturn]] virtual void Abort(const std::string& message, int status) = 0;
};

}  // namespace dba
