// Progress of long phases on a terminal: "\r<phase> 45% (12 s, about 15 s
// left)" on stderr, at most four updates a second, cleared when the phase
// ends. Off unless EnableProgress(true) was called and stderr is a terminal
// (files and pipes get only the per-iteration log), and off on all but the
// calling process's main rank (the caller decides).
//
// Thread safety: Report may be called from any thread; only the first
// thread of a parallel loop should (it sees its own share of the work).
#pragma once

namespace dba {

void EnableProgress(bool on);
bool ProgressEnabled();

// A phase in progress: Report(fraction) as it goes; the destructor clears
// the line. Cheap when progress is off.
class ProgressPhase {
 public:
  explicit ProgressPhase(const char* name);
  ~ProgressPhase();
  ProgressPhase(const ProgressPhase&) = delete;
  ProgressPhase& operator=(const ProgressPhase&) = delete;
  // fraction in [0, 1] of the phase done.
  void Report(double fraction);

 private:
  const char* name_;
  bool on_;
  double start_ = 0.0, last_ = 0.0;
  bool printed_ = false;
};

}  // namespace dba
