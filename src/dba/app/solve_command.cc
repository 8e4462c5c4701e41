// `dba solve`; see solve_command.h.
#include "dba/app/solve_command.h"

#include <omp.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <thread>

#include "dba/common/memory.h"
#include "dba/common/timer.h"
#include "dba/io/atomic_file.h"
#include "dba/io/bal_reader.h"
#include "dba/io/bal_writer.h"
#include "dba/lm/bundle_adjust.h"

namespace dba {
namespace {

int DefaultThreads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

double ParseDouble(const std::string& flag, const std::string& value) {
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != value.size() || !std::isfinite(v) || v < 0) {
    throw std::invalid_argument(flag + ": expected a non-negative number, got '" +
                                value + "'");
  }
  return v;
}

int ParseInt(const std::string& flag, const std::string& value, int min) {
  size_t used = 0;
  long v = 0;
  try {
    v = std::stol(value, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != value.size() || v < min || v > 1000000000L) {
    throw std::invalid_argument(flag + ": expected an integer >= " +
                                std::to_string(min) + ", got '" + value + "'");
  }
  return static_cast<int>(v);
}

std::string Bytes(int64_t b) {
  char buf[64];
  if (b >= (int64_t{1} << 30)) {
    std::snprintf(buf, sizeof buf, "%.2f GiB", b / double(int64_t{1} << 30));
  } else if (b >= (1 << 20)) {
    std::snprintf(buf, sizeof buf, "%.1f MiB", b / double(1 << 20));
  } else {
    std::snprintf(buf, sizeof buf, "%.1f KiB", b / 1024.0);
  }
  return buf;
}

}  // namespace

void PrintSolveHelp(std::ostream& out) {
  const LmOptions d;
  out << "Usage: dba solve INPUT [options]\n"
         "\n"
         "Bundle-adjusts the BAL problem INPUT (plain text or .bz2) with exact\n"
         "Levenberg-Marquardt: the reduced camera system is formed point by point\n"
         "in BSMC and solved by block-Jacobi PCG. Prints one line per iteration\n"
         "and a summary.\n"
         "\n"
         "Options:\n"
         "  -o, --output FILE          write the adjusted problem as BAL (.bz2: compressed);\n"
         "                             written to a temporary name, renamed when complete\n"
         "  --report FILE.json         write the summary and per-iteration log as JSON\n"
         "  -t, --threads N            threads (default: all cores, " << DefaultThreads() << " here)\n"
         "  --max-iterations N         LM iteration limit (default " << d.max_iterations << ")\n"
         "  --function-tolerance X     stop when a step lowers the cost by less than\n"
         "                             this fraction (default " << d.function_tolerance << ")\n"
         "  --gradient-tolerance X     stop when max|J^T r| <= X (default " << d.gradient_tolerance << ")\n"
         "  --parameter-tolerance X    stop when |step| <= X (|x| + X) (default " << d.parameter_tolerance << ")\n"
         "  --initial-lambda X         initial LM damping (default " << d.initial_lambda << ")\n"
         "  --pcg-tolerance X          PCG relative residual (default " << d.pcg.relative_tolerance << ")\n"
         "  --pcg-max-iterations N     PCG iteration limit (default " << d.pcg.max_iterations << ")\n"
         "  -q, --quiet                no per-iteration log\n"
         "  -h, --help                 this text\n"
         "\n"
         "Exit status: 0 on success (whatever the termination reason), 1 on bad\n"
         "input or failure, 2 on bad arguments.\n";
}

SolveCommandOptions ParseSolveArguments(const std::vector<std::string>& args,
                                        bool* help) {
  SolveCommandOptions o;
  o.lm.num_threads = DefaultThreads();
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
    } else if (a == "-t" || a == "--threads") {
      o.lm.num_threads = ParseInt(a, value(), 1);
    } else if (a == "--max-iterations") {
      o.lm.max_iterations = ParseInt(a, value(), 0);
    } else if (a == "--function-tolerance") {
      o.lm.function_tolerance = ParseDouble(a, value());
    } else if (a == "--gradient-tolerance") {
      o.lm.gradient_tolerance = ParseDouble(a, value());
    } else if (a == "--parameter-tolerance") {
      o.lm.parameter_tolerance = ParseDouble(a, value());
    } else if (a == "--initial-lambda") {
      o.lm.initial_lambda = ParseDouble(a, value());
      if (o.lm.initial_lambda <= 0) throw std::invalid_argument(a + ": must be > 0");
    } else if (a == "--pcg-tolerance") {
      o.lm.pcg.relative_tolerance = ParseDouble(a, value());
    } else if (a == "--pcg-max-iterations") {
      o.lm.pcg.max_iterations = ParseInt(a, value(), 1);
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

int RunSolveCommand(const SolveCommandOptions& options, std::ostream& out) {
  Timer load_timer;
  BalProblem problem = ReadBal(options.input);
  const double load_seconds = load_timer.Seconds();
  const int64_t num_obs = problem.num_observations();
  out << "dba solve " << options.input << ": " << problem.num_cameras()
      << " cameras, " << problem.num_points() << " points, " << num_obs
      << " observations, " << options.lm.num_threads << " threads\n";


  if (!options.quiet) {
    out << "iter        cost     rms_px   max|grad|     lambda  pcg  accept    time_s\n";
  }
  auto log = [&](const IterationSummary& it) {
    if (options.quiet) return;
    char line[160];
    std::snprintf(line, sizeof line,
                  "%4d %12.6e %9.4f %11.3e %10.3e %4d %7s %9.3f\n",
                  it.iteration, it.cost, it.rms_pixels, it.gradient_max_norm,
                  it.lambda, it.pcg_iterations, it.step_accepted ? "yes" : "no",
                  it.seconds);
    out << line << std::flush;
  };
  const BundleAdjustSummary ba = BundleAdjust(options.lm, &problem, log);
  const LmSummary& summary = ba.lm;
  const double setup_seconds = ba.symbolic_seconds;
  const RcsFootprint& rcs = ba.rcs;

  Timer write_timer;
  if (!options.output.empty()) WriteBal(problem, options.output);
  const double write_seconds = write_timer.Seconds();

  const int64_t peak = PeakResidentBytes();
  const int64_t problem_bytes = problem.MemoryBytes();
  char buf[256];
  out << "\nSummary\n";
  std::snprintf(buf, sizeof buf, "  initial cost        %.6e  (RMS %.4f px)\n",
                summary.initial_cost, summary.Rms(summary.initial_cost));
  out << buf;
  std::snprintf(buf, sizeof buf, "  final cost          %.6e  (RMS %.4f px)\n",
                summary.final_cost, summary.Rms(summary.final_cost));
  out << buf;
  out << "  iterations          " << summary.iterations << " ("
      << summary.accepted_iterations << " accepted, "
      << summary.total_pcg_iterations << " PCG iterations)\n";
  out << "  termination         " << TerminationReasonName(summary.termination)
      << ": " << summary.termination_message << "\n";
  std::snprintf(buf, sizeof buf,
                "  time (s)            load %.3f  setup %.3f  rcs %.3f  pcg %.3f  "
                "back-substitution %.3f  write %.3f  total %.3f\n",
                load_seconds, setup_seconds, summary.times.rcs_formation,
                summary.times.pcg, summary.times.back_substitution,
                write_seconds,
                load_seconds + setup_seconds + summary.times.total + write_seconds);
  out << buf;
  out << "  RCS (BSMC)          " << rcs.block_rows << " block rows, "
      << rcs.blocks << " blocks, "
      << Bytes(rcs.bsmc_structure_bytes + rcs.bsmc_value_bytes)
      << " (CSR: " << Bytes(rcs.csr_bytes) << ")\n";
  std::snprintf(buf, sizeof buf, "  memory              peak %s, %.1f bytes/observation "
                "(problem data %.1f bytes/observation)\n",
                Bytes(peak).c_str(), double(peak) / std::max<int64_t>(num_obs, 1),
                double(problem_bytes) / std::max<int64_t>(num_obs, 1));
  out << buf;
  if (!options.output.empty()) out << "  output              " << options.output << "\n";

  if (!options.report_path.empty()) {
    nlohmann::ordered_json j;
    j["input"] = options.input;
    j["num_cameras"] = problem.num_cameras();
    j["num_points"] = problem.num_points();
    j["num_observations"] = num_obs;
    j["threads"] = options.lm.num_threads;
    j["initial_cost"] = summary.initial_cost;
    j["final_cost"] = summary.final_cost;
    j["initial_rms_px"] = summary.Rms(summary.initial_cost);
    j["final_rms_px"] = summary.Rms(summary.final_cost);
    j["iterations"] = summary.iterations;
    j["accepted_iterations"] = summary.accepted_iterations;
    j["pcg_iterations"] = summary.total_pcg_iterations;
    j["termination"] = TerminationReasonName(summary.termination);
    j["termination_message"] = summary.termination_message;
    j["seconds"] = {{"load", load_seconds},
                    {"setup", setup_seconds},
                    {"rcs_formation", summary.times.rcs_formation},
                    {"pcg", summary.times.pcg},
                    {"back_substitution", summary.times.back_substitution},
                    {"write", write_seconds},
                    {"total", load_seconds + setup_seconds + summary.times.total + write_seconds}};
    j["memory"] = {{"peak_bytes", peak},
                   {"peak_bytes_per_observation", double(peak) / std::max<int64_t>(num_obs, 1)},
                   {"problem_bytes", problem_bytes},
                   {"rcs_bsmc_structure_bytes", rcs.bsmc_structure_bytes},
                   {"rcs_bsmc_value_bytes", rcs.bsmc_value_bytes},
                   {"rcs_csr_bytes", rcs.csr_bytes},
                   {"rcs_blocks", rcs.blocks}};
    nlohmann::ordered_json history = nlohmann::ordered_json::array();
    for (const IterationSummary& it : summary.history) {
      history.push_back({{"iteration", it.iteration},
                         {"cost", it.cost},
                         {"rms_px", it.rms_pixels},
                         {"gradient_max_norm", it.gradient_max_norm},
                         {"lambda", it.lambda},
                         {"pcg_iterations", it.pcg_iterations},
                         {"pcg_relative_residual", it.pcg_relative_residual},
                         {"candidate_cost", it.candidate_cost},
                         {"gain_ratio", it.gain_ratio},
                         {"accepted", it.step_accepted},
                         {"seconds", it.seconds}});
    }
    j["history"] = history;
    WriteFileAtomically(options.report_path, j.dump(2) + "\n");
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
  try {
    return RunSolveCommand(options, std::cout);
  } catch (const std::exception& e) {
    std::cerr << "dba solve: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace dba
