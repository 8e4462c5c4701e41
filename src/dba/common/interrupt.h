// A solve stopped from outside, on request (Python's Ctrl-C: the
// extension's dba.solve and dba.solve_arrays). The host installs a check on
// the thread that runs the solve for the solve's duration; the solve polls
// it on that thread between its steps (each LM iteration, each PCG
// iteration), never inside a parallel region, and the check throws to stop
// it (whatever it throws unwinds the solve: nothing is written). Polls on
// other threads, or with no check installed (the command line, where
// SIGINT ends the process), do nothing.
//
// Thread safety: a check is the installing thread's own (thread_local).
#pragma once

#include <functional>

namespace dba {

// Installs `check` for this thread while it lives (the previous one after).
class InterruptCheck {
 public:
  explicit InterruptCheck(std::function<void()> check);
  ~InterruptCheck();
  InterruptCheck(const InterruptCheck&) = delete;
  InterruptCheck& operator=(const InterruptCheck&) = delete;

 private:
  std::function<void()> check_;
  const std::function<void()>* previous_;
};

// Runs this thread's check, if any (it may throw).
void PollInterrupt();

}  // namespace dba
