// Reads a BAL problem (text or .bz2), bundle-adjusts it with dba's exact
// Levenberg-Marquardt and prints one line per iteration and the result:
//
//   bundle_adjust_bal PROBLEM [THREADS]
//
// The smallest use of the installed library (find_package(dba), dba::dba).
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "dba/io/read_problem.h"
#include "dba/lm/bundle_adjust.h"

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: %s PROBLEM [THREADS]\n", argv[0]);
    return 2;
  }
  try {
    dba::Problem problem = dba::ReadProblem(argv[1]);
    dba::LmOptions options;
    options.num_threads = argc == 3 ? std::atoi(argv[2]) : 1;
    std::printf("%lld cameras, %lld points, %lld observations\n",
                static_cast<long long>(problem.num_images()),
                static_cast<long long>(problem.num_points()),
                static_cast<long long>(problem.num_observations()));
    const dba::BundleAdjustSummary s =
        dba::BundleAdjust(options, &problem, [](const dba::IterationSummary& it) {
          std::printf("iteration %3d  cost %.6e  %s\n", it.iteration, it.cost,
                      it.step_accepted ? "accepted" : "rejected");
        });
    std::printf("initial cost %.6e\nfinal cost %.6e\niterations %d\ntermination %s\n",
                s.lm.initial_cost, s.lm.final_cost, s.lm.iterations,
                dba::TerminationReasonName(s.lm.termination));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
