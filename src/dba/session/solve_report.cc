// A solve's report: the rest of its time and the iteration log's lines; see solve_report.h.
#include "dba/session/solve_report.h"

#include <cstdio>

namespace dba {

double SolveReport::OtherSeconds() const {
  const PhaseTimes& lm = solve.ba.lm.times;
  return total_seconds - (startup_seconds + read_seconds + load_seconds +
                          solve.distribution_seconds + solve.ba.symbolic_seconds +
                          lm.rcs_formation + lm.linear_solve + lm.back_substitution + analysis_seconds +
                          write_seconds);
}

std::string IterationLogHeader() {
  return "iter        cost     rms_px   max|grad|     lambda  linear (iter, stop)      accept    time_s\n";
}

std::string IterationLogLine(const IterationSummary& it) {
  char line[200];
  std::snprintf(line, sizeof line, "%4d %12.6e %9.4f %11.3e %10.3e  %5d %-18s %6s %9.3f\n",
                it.iteration, it.cost, it.rms_pixels, it.gradient_max_norm, it.lambda,
                it.linear_iterations, it.linear_stop.c_str(), it.step_accepted ? "yes" : "no",
                it.seconds);
  return line;
}

}  // namespace dba
