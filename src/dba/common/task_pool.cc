// Worker threads over two task queues; see task_pool.h.
#include "dba/common/task_pool.h"

#include <algorithm>

namespace dba {

TaskPool::TaskPool(int threads) {
  const int n = std::max(1, threads);
  workers_.reserve(n);
  for (int i = 0; i < n; ++i) workers_.emplace_back([this] { Work(); });
}

TaskPool::~TaskPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  work_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void TaskPool::Submit(std::function<void()> task, bool urgent) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    (urgent ? urgent_ : normal_).push_back(std::move(task));
  }
  work_.notify_one();
}

void TaskPool::WaitUntil(const std::function<bool()>& ready) {
  std::unique_lock<std::mutex> lock(mutex_);
  ended_.wait(lock, ready);
}

void TaskPool::Work() {
  for (;;) {
    std::function<void()> task;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      work_.wait(lock, [&] { return stop_ || !urgent_.empty() || !normal_.empty(); });
      if (stop_) return;
      std::deque<std::function<void()>>& queue = urgent_.empty() ? normal_ : urgent_;
      task = std::move(queue.front());
      queue.pop_front();
    }
    task();
    task = nullptr;  // what it holds is released before the waiter looks
    {
      std::lock_guard<std::mutex> lock(mutex_);
    }
    ended_.notify_all();
  }
}

}  // namespace dba
