// N ranks as threads of one process; see thread_transport.h.
#include "dba/cluster/thread_transport.h"

#include <algorithm>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <exception>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <tuple>

namespace dba {

// Channels keep point-to-point messages apart from collectives, as MPI's
// communicator contexts do.
enum Channel : int { kPointToPoint, kBroadcast, kGather, kExchange, kReduce, kReduced };

// The ranks' mailboxes: (from, to, channel) -> messages in order.
class ThreadGroup {
 public:
  explicit ThreadGroup(int size) : size_(size) {}
  int size() const { return size_; }

  void Put(int from, int to, int channel, const void* data, uint64_t bytes) {
    const char* p = static_cast<const char*>(data);
    std::lock_guard<std::mutex> lock(mutex_);
    boxes_[{from, to, channel}].emplace_back(p, p + bytes);
    ready_.notify_all();
  }
  // Waits until a message from `from` to `to` is there; throws when a rank
  // aborted.
  void WaitFor(int from, int to, int channel) {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait(lock, [&] { return aborted_ || !boxes_[{from, to, channel}].empty(); });
    if (aborted_) throw std::runtime_error("another rank aborted: " + reason_);
  }
  void Take(int from, int to, int channel, void* data, uint64_t bytes) {
    WaitFor(from, to, channel);
    std::lock_guard<std::mutex> lock(mutex_);
    auto& box = boxes_[{from, to, channel}];
    if (box.front().size() != bytes) {
      throw std::logic_error("rank " + std::to_string(to) + " expected " + std::to_string(bytes) +
                             " bytes from rank " + std::to_string(from) + ", the message has " +
                             std::to_string(box.front().size()));
    }
    if (bytes > 0) std::memcpy(data, box.front().data(), bytes);
    box.pop_front();
  }
  void Abort(const std::string& reason) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!aborted_) reason_ = reason;
    aborted_ = true;
    ready_.notify_all();
  }

 private:
  const int size_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::map<std::tuple<int, int, int>, std::deque<std::vector<char>>> boxes_;
  bool aborted_ = false;
  std::string reason_;
};

namespace {

class ThreadTransport : public Transport {
 public:
  ThreadTransport(std::shared_ptr<ThreadGroup> group, int rank) : group_(std::move(group)), rank_(rank) {}
  int rank() const override { return rank_; }
  int size() const override { return group_->size(); }
  int ranks_on_node() const override { return group_->size(); }

  void Send(int dest, const void* data, uint64_t bytes) override {
    group_->Put(rank_, dest, kPointToPoint, data, bytes);
  }
  void WaitFor(int source) override { group_->WaitFor(source, rank_, kPointToPoint); }
  void Recv(int source, void* data, uint64_t bytes) override {
    group_->Take(source, rank_, kPointToPoint, data, bytes);
  }

  void Broadcast(void* data, uint64_t bytes) override {
    if (rank_ != 0) {
      group_->Take(0, rank_, kBroadcast, data, bytes);
      return;
    }
    for (int r = 1; r < size(); ++r) group_->Put(0, r, kBroadcast, data, bytes);
  }

  void Gather(const double* local, uint64_t count, double* all) override {
    if (rank_ != 0) {
      group_->Put(rank_, 0, kGather, local, 8 * count);
      return;
    }
    std::copy_n(local, count, all);
    for (int r = 1; r < size(); ++r) group_->Take(r, 0, kGather, all + r * count, 8 * count);
  }

  void Exchange(const std::vector<Span>& send, const std::vector<Span>& recv) override {
    for (int r = 0; r < size(); ++r) {
      if (r != rank_ && send[r].bytes > 0) group_->Put(rank_, r, kExchange, send[r].data, send[r].bytes);
    }
    for (int r = 0; r < size(); ++r) {
      if (r != rank_ && recv[r].bytes > 0) group_->Take(r, rank_, kExchange, recv[r].data, recv[r].bytes);
    }
  }

  // Through rank 0, in rank order: the same sum on every run.
  void Allreduce(void* data, int64_t count, bool is_double, bool max) override {
    const uint64_t bytes = 8 * static_cast<uint64_t>(count);
    if (rank_ != 0) {
      group_->Put(rank_, 0, kReduce, data, bytes);
      group_->Take(0, rank_, kReduced, data, bytes);
      return;
    }
    std::vector<char> theirs(bytes);
    for (int r = 1; r < size(); ++r) {
      group_->Take(r, 0, kReduce, theirs.data(), bytes);
      if (is_double) {
        Combine(static_cast<double*>(data), reinterpret_cast<const double*>(theirs.data()), count, max);
      } else {
        Combine(static_cast<int64_t*>(data), reinterpret_cast<const int64_t*>(theirs.data()), count, max);
      }
    }
    for (int r = 1; r < size(); ++r) group_->Put(0, r, kReduced, data, bytes);
  }

  [[noreturn]] void Abort(const std::string& message, int) override {
    group_->Abort("rank " + std::to_string(rank_) + ": " + message);
    throw std::runtime_error(message);
  }

 private:
  template <typename T>
  static void Combine(T* into, const T* from, int64_t count, bool max) {
    for (int64_t i = 0; i < count; ++i) into[i] = max ? std::max(into[i], from[i]) : into[i] + from[i];
  }

  std::shared_ptr<ThreadGroup> group_;
  int rank_;
};

}  // namespace

void RunRanksAsThreads(int ranks, const std::function<void(Communicator& comm)>& body) {
  auto group = std::make_shared<ThreadGroup>(ranks);
  std::mutex first_mutex;
  std::exception_ptr first;  // the error that ended the others
  std::vector<std::thread> threads;
  for (int r = 0; r < ranks; ++r) {
    threads.emplace_back([&, r] {
      try {
        Communicator comm(std::make_unique<ThreadTransport>(group, r));
        body(comm);
      } catch (...) {
        {
          std::lock_guard<std::mutex> lock(first_mutex);
          if (!first) first = std::current_exception();
        }
        group->Abort("rank " + std::to_string(r) + " failed");
      }
    });
  }
  for (std::thread& t : threads) t.join();
  if (first) std::rethrow_exception(first);
}

}  // namespace dba
