// A host's check: polled on the thread that installed it only, restored
// after its scope, and what it throws reaches the poller.
#include "dba/common/interrupt.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <thread>

namespace dba {
namespace {

TEST(Interrupt, TheCheckIsTheInstallingThreadsOwnWhileItLives) {
  PollInterrupt();  // nothing installed: nothing happens
  int outer = 0, inner = 0;
  {
    const InterruptCheck a([&] { ++outer; });
    PollInterrupt();
    {
      const InterruptCheck b([&] { ++inner; });
      PollInterrupt();
      std::thread other([] { PollInterrupt(); });  // not this thread's check
      other.join();
    }
    PollInterrupt();  // a again
  }
  PollInterrupt();
  EXPECT_EQ(outer, 2);
  EXPECT_EQ(inner, 1);
  const InterruptCheck stop([] { throw std::runtime_error("stop"); });
  EXPECT_THROW(PollInterrupt(), std::runtime_error);
}

}  // namespace
}  // namespace dba
