// `dba solve`; see solve_command.h.
#include "dba/app/solve_command.h"

#include <omp.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <thread>

#include "dba/common/memory.h"
#include "dba/common/timer.h"
#include "dba/io/atomic_file.h"
#include "dba/io/read_problem.h"
#include "dba/io/bal_writer.h"
#include "dba/app/arguments.h"
#include "dba/app/solve_report.h"
#include "dba/synthetic/ground_truth.h"
#include "dba/lm/bundle_adjust.h"

namespace dba {
namespace {

int DefaultThreads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

}  // namespace

void PrintSolveHelp(std::ostream& out) {
  const LmOptions d;
  out << "Usage: dba solve INPUT [options]\n"
         "\n"
         "Bundle-adjusts the problem INPUT (BAL text, plain or .bz2, or a .dba file\n"
         "with BAL cameras or poses and shared intrinsics) with exact\n"
         "Levenberg-Marquardt: the reduced camera system is formed point by point\n"
         "in BSMC and solved by block-Jacobi PCG. Prints one line per iteration\n"
         "and a summary.\n"
         "\n"
         "Distributed: started by mpirun or srun with N ranks, the points are split\n"
         "over the ranks, each forms its sub-RCS, rank 0 aggregates and solves.\n"
         "\n"
         "Options:\n"
         "  -o, --output FILE          write the adjusted problem: .dba binary, else BAL text\n"
         "                             (.bz2: compressed; not for photogrammetric problems);\n"
         "                             written to a temporary name, renamed when complete\n"
         "  --report FILE.json         write the summary and per-iteration log as JSON\n"
         "  --truth FILE               ground truth of a generated problem (dba generate\n"
         "                             --truth): report the RMS against the noise-free\n"
         "                             observations, the camera/point errors after a\n"
         "                             similarity alignment and, photogrammetric model,\n"
         "                             each intrinsic group's errors (f, cx, cy, k1, k2)\n"
         "  -t, --threads N            threads per rank (default: the node's cores divided\n"
         "                             by its ranks; " << DefaultThreads() << " cores here)\n"
         "  --max-iterations N         LM iteration limit (default " << d.max_iterations << ")\n"
         "  --function-tolerance X     stop when a step lowers the cost by less than\n"
         "                             this fraction (default " << d.function_tolerance << ")\n"
         "  --gradient-tolerance X     stop when max|J^T r| <= X (default " << d.gradient_tolerance << ")\n"
         "  --parameter-tolerance X    stop when |step| <= X (|x| + X) (default " << d.parameter_tolerance << ")\n"
         "  --initial-lambda X         initial LM damping (default " << d.initial_lambda << ")\n"
         "  --pcg-tolerance X          PCG relative residual (default " << d.pcg.relative_tolerance << ")\n"
         "  --pcg-max-iterations N     PCG iteration limit (default " << d.pcg.max_iterations << ")\n"
         "  --partition equal|cameras  how points are split over MPI ranks: 'equal' (the\n"
         "                             paper's equal counts) or 'cameras' (grouped by the\n"
         "                             cameras that see them; default)\n"
         "  --main-rank auto|forms|coordinates\n"
         "                             whether rank 0 also forms a sub-RCS (auto: yes for\n"
         "                             up to 4 ranks)\n"
         "  -q, --quiet                no per-iteration log\n"
         "  -h, --help                 this text\n"
         "\n"
         "Exit status: 0 on success (whatever the termination reason), 1 on bad\n"
         "input or failure, 2 on bad arguments.\n";
}

SolveCommandOptions ParseSolveArguments(const std::vector<std::string>& args,
                                        bool* help) {
  SolveCommandOptions o;
  o.lm.num_threads = 0;  // auto: the node's cores divided by its ranks
  *help = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw std::invalid_argument(a + ": missing value");
      return args[++i];
    };
    if (a == "-h" || a == "--help") {
      *help = true;
      return o;
    } else if (a == "-o" || a == "--output") {
      o.output = value();
    } else if (a == "--report") {
      o.report_path = value();
    } else if (a == "--truth") {
      o.truth_path = value();
    } else if (a == "-t" || a == "--threads") {
      o.lm.num_threads = static_cast<int>(ParseIntegerArgument(a, value(), 1, 1000000000));
    } else if (a == "--max-iterations") {
      o.lm.max_iterations = static_cast<int>(ParseIntegerArgument(a, value(), 0, 1000000000));
    } else if (a == "--function-tolerance") {
      o.lm.function_tolerance = ParseNumberArgument(a, value());
    } else if (a == "--gradient-tolerance") {
      o.lm.gradient_tolerance = ParseNumberArgument(a, value());
    } else if (a == "--parameter-tolerance") {
      o.lm.parameter_tolerance = ParseNumberArgument(a, value());
    } else if (a == "--initial-lambda") {
      o.lm.initial_lambda = ParseNumberArgument(a, value());
      if (o.lm.initial_lambda <= 0) throw std::invalid_argument(a + ": must be > 0");
    } else if (a == "--pcg-tolerance") {
      o.lm.pcg.relative_tolerance = ParseNumberArgument(a, value());
    } else if (a == "--pcg-max-iterations") {
      o.lm.pcg.max_iterations = static_cast<int>(ParseIntegerArgument(a, value(), 1, 1000000000));
    } else if (a == "--partition") {
      o.distributed.partition = ParsePartitionScheme(value());
    } else if (a == "--main-rank") {
      const std::string& v = value();
      using Role = DistributedOptions::MainRole;
      if (v == "auto") o.distributed.main_role = Role::kAuto;
      else if (v == "forms") o.distributed.main_role = Role::kForms;
      else if (v == "coordinates") o.distributed.main_role = Role::kCoordinates;
      else throw std::invalid_argument(a + ": expected auto, forms or coordinates, got '" + v + "'");
    } else if (a == "-q" || a == "--quiet") {
      o.quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      throw std::invalid_argument("unknown option '" + a + "' (see dba solve --help)");
    } else if (o.input.empty()) {
      o.input = a;
    } else {
      throw std::invalid_argument("more than one input file: '" + o.input +
                                  "' and '" + a + "'");
    }
  }
  if (o.input.empty()) throw std::invalid_argument("missing INPUT (see dba solve --help)");
  return o;
}

int RunSolveCommand(const SolveCommandOptions& options, Communicator* comm,
                    std::ostream& out) {
  const bool main = comm->is_main();
  LmOptions lm = options.lm;
  if (lm.num_threads == 0) {
    lm.num_threads = std::max(1, DefaultThreads() / comm->ranks_on_node());
  }
  SolveReport report;
  report.input = options.input;
  report.threads = lm.num_threads;
  BalProblem problem;
  // Distributed runs on a binary file: every rank reads its own points.
  const bool ranks_read_file = comm->size() > 1 && IsBinaryProblem(options.input);
  if (main) {
    Timer load_timer;
    CameraModel model = CameraModel::kBal;
    if (ranks_read_file) {
      const BinaryProblemHeader h = ReadBinaryProblemHeader(options.input);
      model = h.model;
      report.num_cameras = h.num_cameras;
      report.num_points = h.num_points;
      report.num_observations = h.num_observations;
    } else {
      problem = ReadProblem(options.input);
      model = problem.model;
      report.num_cameras = problem.num_cameras();
      report.num_points = problem.num_points();
      report.num_observations = problem.num_observations();
      report.problem_bytes = problem.MemoryBytes();
    }
    const std::string& o = options.output;
    if (model == CameraModel::kPhoto && !o.empty() &&
        !(o.size() >= 4 && o.compare(o.size() - 4, 4, ".dba") == 0)) {
      // Refused before the solve, not after it.
      throw std::invalid_argument("-o " + o + ": " + options.input +
                                  " is a photogrammetric problem and BAL text cannot hold "
                                  "shared intrinsics; write a .dba file");
    }
    report.load_seconds = load_timer.Seconds();
    out << "dba solve " << options.input << ": " << report.num_cameras << " cameras, "
        << report.num_points << " points, " << report.num_observations
        << " observations, " << comm->size() << (comm->size() == 1 ? " rank, " : " ranks, ")
        << lm.num_threads << " threads" << (comm->size() == 1 ? "" : " per rank") << "\n";
    if (!options.quiet) {
      // Large problems spend a while here before the first iteration line.
      char line[160];
      std::snprintf(line, sizeof line,
                    "loaded in %.1f s; building the RCS structure, then one line per "
                    "LM iteration\n",
                    report.load_seconds);
      out << line << IterationLogHeader() << std::flush;
    }
  }
  auto log = [&](const IterationSummary& it) {
    if (!options.quiet) out << IterationLogLine(it) << std::flush;
  };
  if (comm->size() == 1) {
    report.solve.ba = BundleAdjust(lm, &problem, log);
  } else {
    report.solve = DistributedBundleAdjust(comm, lm, options.distributed,
                                           ranks_read_file ? options.input : std::string(),
                                           !options.output.empty() || !options.truth_path.empty(),
                                           &problem, log);
  }
  if (!main) return 0;

  Timer write_timer;
  if (!options.output.empty()) {
    const bool binary_out = options.output.size() >= 4 &&
                            options.output.compare(options.output.size() - 4, 4, ".dba") == 0;
    if (comm->size() > 1 && ranks_read_file && binary_out) {
      // Binary to binary: stream the observations from the input.
      WriteBinaryWithNewParameters(options.input, options.output, problem.cameras,
                                   problem.points);
    } else {
      if (comm->size() > 1) {
        // The observations were handed to the ranks: read them again.
        BalProblem full = ReadProblem(options.input);
        full.cameras.swap(problem.cameras);
        full.points.swap(problem.points);
        problem = std::move(full);
      }
      WriteProblem(problem, options.output);
    }
  }
  report.write_seconds = write_timer.Seconds();
  if (!options.truth_path.empty()) {
    report.truth = CompareWithGroundTruthFile(options.truth_path, problem.cameras,
                                              problem.points, problem.model);
    report.has_truth = true;
  }
  report.peak_memory_bytes = PeakResidentBytes();
  PrintSolveReport(report, out);
  if (!options.output.empty()) out << "  output              " << options.output << "\n";
  if (!options.report_path.empty()) {
    WriteFileAtomically(options.report_path, SolveReportJson(report));
    out << "  report              " << options.report_path << "\n";
  }
  return 0;
}

int SolveMain(const std::vector<std::string>& args) {
  SolveCommandOptions options;
  try {
    bool help = false;
    options = ParseSolveArguments(args, &help);
    if (help) {
      PrintSolveHelp(std::cout);
      return 0;
    }
  } catch (const std::exception& e) {
    std::cerr << "dba solve: " << e.what() << "\n";
    return 2;
  }
  Communicator comm(nullptr, nullptr);
  try {
    return RunSolveCommand(options, &comm, std::cout);
  } catch (const std::exception& e) {
    if (comm.size() > 1) comm.Abort(e.what());  // ends every rank
    std::cerr << "dba solve: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace dba
