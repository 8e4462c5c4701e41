// Tests of TaskPool: every task runs once, urgent ones before the ordinary
// ones queued earlier, WaitUntil returns once its condition holds.
#include "dba/common/task_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <future>
#include <mutex>
#include <vector>

namespace dba {
namespace {

TEST(TaskPoolTest, EveryTaskRunsOnce) {
  std::vector<std::atomic<int>> runs(1000);
  std::atomic<int> ended{0};
  {
    TaskPool pool(3);
    EXPECT_EQ(pool.threads(), 3);
    for (size_t i = 0; i < runs.size(); ++i) {
      pool.Submit([&, i] {
        ++runs[i];
        ++ended;
      }, i % 2 == 0);
    }
    pool.WaitUntil([&] { return ended.load() == 1000; });
  }
  for (const auto& r : runs) EXPECT_EQ(r.load(), 1);
}

TEST(TaskPoolTest, UrgentTasksGoFirst) {
  TaskPool pool(1);
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<int> ended{0};
  std::mutex m;
  std::vector<int> order;
  // The one worker is held while both kinds are queued.
  pool.Submit([released] { released.wait(); });
  for (int i = 0; i < 3; ++i) {
    pool.Submit([&, i] {
      std::lock_guard<std::mutex> lock(m);
      order.push_back(i);
      ++ended;
    });
  }
  for (int i = 10; i < 13; ++i) {
    pool.Submit([&, i] {
      std::lock_guard<std::mutex> lock(m);
      order.push_back(i);
      ++ended;
    }, true);
  }
  release.set_value();
  pool.WaitUntil([&] { return ended.load() == 6; });
  EXPECT_EQ(order, (std::vector<int>{10, 11, 12, 0, 1, 2}));
}

}  // namespace
}  // namespace dba
