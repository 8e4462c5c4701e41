// A fixed set of worker threads running tasks in submission order, urgent
// tasks first: the readers' pipeline (docs/design.md §4.3) decodes bzip2
// blocks ahead as ordinary tasks and parses the text handed out as urgent
// ones, so the text already decoded is parsed (and its memory released)
// before more is decoded.
//
// Tasks must not throw (a task catches and records its own errors) and mark
// their own completion; WaitUntil re-checks a condition each time a task
// ends. The destructor drops the tasks not yet started and joins the
// workers: whatever a queued task refers to must outlive the pool or not be
// touched by it once its owner is gone (the readers wait for their tasks).
//
// Thread safety: Submit and WaitUntil from any thread.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace dba {

class TaskPool {
 public:
  explicit TaskPool(int threads);
  ~TaskPool();
  TaskPool(const TaskPool&) = delete;
  TaskPool& operator=(const TaskPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()); }

  void Submit(std::function<void()> task, bool urgent = false);
  // Returns once `ready()` holds; it is evaluated under the pool's lock, so
  // a task that sets what it reads before returning is never missed.
  void WaitUntil(const std::function<bool()>& ready);

 private:
  void Work();

  std::mutex mutex_;
  std::condition_variable work_;   // a task was queued, or stop
  std::condition_variable ended_;  // a task ended
  std::deque<std::function<void()>> urgent_;
  std::deque<std::function<void()>> normal_;
  bool stop_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace dba
