#include "dba/common/process_start.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <string>
#include <thread>

namespace dba {
namespace {

// A /proc/PID/stat line whose field 22 (starttime) is `ticks`, after a
// command name with a space and a parenthesis.
std::string StatLine(const std::string& ticks) {
  std::string line = "4242 (dba x) y) S";
  for (int field = 4; field <= 21; ++field) line += " " + std::to_string(field);
  return line + " " + ticks + " 23 24\n";
}

TEST(ProcessStart, FieldTwentyTwoAtTheMiddleOfItsTick) {
  // Started in tick 500 (5.00-5.01 s after boot at 100 ticks a second).
  EXPECT_NEAR(ProcessAgeSeconds(StatLine("500"), 7.0, 100), 7.0 - 5.005, 1e-12);
  // Asked within its tick: the start lies between the tick and now.
  EXPECT_NEAR(ProcessAgeSeconds(StatLine("500"), 5.004, 100), 0.002, 1e-12);
  EXPECT_NEAR(ProcessAgeSeconds(StatLine("250"), 3.0, 250), 2.0 - 0.002, 1e-12);
}

TEST(ProcessStart, UnparsableIsUnknown) {
  EXPECT_EQ(ProcessAgeSeconds("4242 (dba) S 1 2 3", 7.0, 100), -1.0);
  EXPECT_EQ(ProcessAgeSeconds(StatLine("5x0"), 7.0, 100), -1.0);
  EXPECT_EQ(ProcessAgeSeconds("no parenthesis", 7.0, 100), -1.0);
  EXPECT_EQ(ProcessAgeSeconds(StatLine("500"), 4.0, 100), -1.0);  // after now
}

// A child forked now and asked 0.3 s later is 0.3 s old, within half a
// tick, and not older than the parent's clock around it.
TEST(ProcessStart, AForkedChildKnowsItsAge) {
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  const auto before = std::chrono::steady_clock::now();
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const double age = ProcessAgeSeconds();
    ::_exit(::write(fds[1], &age, sizeof age) == sizeof age ? 0 : 1);
  }
  double age = -2.0;
  ASSERT_EQ(::read(fds[0], &age, sizeof age), static_cast<ssize_t>(sizeof age));
  const double around = std::chrono::duration<double>(std::chrono::steady_clock::now() - before).count();
  int status = 0;
  ::waitpid(child, &status, 0);
  ::close(fds[0]);
  ::close(fds[1]);
  const double half_tick = 0.5 / static_cast<double>(::sysconf(_SC_CLK_TCK));
  EXPECT_GE(age, 0.3 - half_tick - 1e-3);
  EXPECT_LE(age, around + half_tick + 1e-3);
}

TEST(ProcessStart, TheRunClockCountsFromTheStart) {
  const double age = ProcessAgeSeconds();
  ASSERT_GE(age, 0.0);
  EXPECT_GE(SinceProcessStart().Seconds(), age);
  EXPECT_NEAR(Timer::StartedAgo(2.5).Seconds(), 2.5, 0.05);
}

}  // namespace
}  // namespace dba
