// Ceres baseline for the comparison benchmarks (issue 3): solves a BAL problem
// with Ceres's public API and the standard BAL reprojection model (the same
// as dba's, data/README.md), and writes a JSON report with the keys of
// `dba solve --report` (initial/final cost and RMS, iterations, termination,
// seconds.total, history of cost and per-iteration seconds).
//
//   ceres_bal INPUT [--solver iterative_schur|sparse_schur] [-t N]
//             [--max-iterations N] [--function-tolerance X] [--report FILE]
#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dba/io/atomic_file.h"
#include "dba/io/read_problem.h"

namespace {

// r = f (1 + k1 |p|² + k2 |p|⁴) p - u,  p = -P.xy / P.z,  P = R(ω) X + t.
struct BalReprojectionError {
  BalReprojectionError(double x, double y) : x(x), y(y) {}
  template <typename T>
  bool operator()(const T* camera, const T* point, T* residual) const {
    T P[3];
    ceres::AngleAxisRotatePoint(camera, point, P);
    P[0] += camera[3];
    P[1] += camera[4];
    P[2] += camera[5];
    const T px = -P[0] / P[2], py = -P[1] / P[2];
    const T r2 = px * px + py * py;
    const T d = T(1.0) + r2 * (camera[7] + camera[8] * r2);
    residual[0] = camera[6] * d * px - T(x);
    residual[1] = camera[6] * d * py - T(y);
    return true;
  }
  double x, y;
};

struct History : public ceres::IterationCallback {
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    entries.push_back({{"iteration", s.iteration},
                       {"cost", s.cost},
                       {"accepted", s.step_is_successful},
                       {"linear_solver_iterations", s.linear_solver_iterations},
                       {"seconds", s.iteration_time_in_seconds},
                       {"cumulative_seconds", s.cumulative_time_in_seconds}});
    return ceres::SOLVER_CONTINUE;
  }
  nlohmann::ordered_json entries = nlohmann::ordered_json::array();
};

int Usage() {
  std::cerr << "Usage: ceres_bal INPUT [--solver iterative_schur|sparse_schur] [-t N]\n"
               "                 [--max-iterations N] [--function-tolerance X] [--report FILE]\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string input, report_path, solver = "iterative_schur";
  int threads = 2, max_iterations = 100;
  double function_tolerance = 1e-6;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + ": missing value");
      return argv[++i];
    };
    try {
      if (a == "--solver") solver = value();
      else if (a == "-t" || a == "--threads") threads = std::stoi(value());
      else if (a == "--max-iterations") max_iterations = std::stoi(value());
      else if (a == "--function-tolerance") function_tolerance = std::stod(value());
      else if (a == "--report") report_path = value();
      else if (!a.empty() && a[0] == '-') return Usage();
      else input = a;
    } catch (const std::exception& e) {
      std::cerr << "ceres_bal: " << e.what() << "\n";
      return Usage();
    }
  }
  if (input.empty()) return Usage();
  try {
    dba::BalProblem p = dba::ReadProblem(input);
    ceres::Problem problem;
    for (int64_t k = 0; k < p.num_points(); ++k) {
      for (int64_t o = p.point_offsets[k]; o < p.point_offsets[k + 1]; ++o) {
        auto* cost = new ceres::AutoDiffCostFunction<BalReprojectionError, 2, 9, 3>(
            new BalReprojectionError(p.obs_pixel[2 * o], p.obs_pixel[2 * o + 1]));
        problem.AddResidualBlock(cost, nullptr, p.camera(p.obs_camera[o]), p.point(k));
      }
    }
    ceres::Solver::Options options;
    if (solver == "iterative_schur") {
      options.linear_solver_type = ceres::ITERATIVE_SCHUR;
      options.preconditioner_type = ceres::SCHUR_JACOBI;
    } else if (solver == "sparse_schur") {
      options.linear_solver_type = ceres::SPARSE_SCHUR;
    } else {
      std::cerr << "ceres_bal: unknown solver '" << solver << "'\n";
      return 2;
    }
    options.num_threads = threads;
    options.max_num_iterations = max_iterations;
    options.function_tolerance = function_tolerance;
    options.minimizer_progress_to_stdout = false;
    History history;
    options.callbacks.push_back(&history);
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    const double n = static_cast<double>(p.num_observations());
    std::printf("ceres_bal %s (%s, %d threads): cost %.6e -> %.6e, RMS %.4f -> %.4f px, "
                "%d iterations, %.3f s, %s\n",
                input.c_str(), solver.c_str(), threads, summary.initial_cost,
                summary.final_cost, std::sqrt(2 * summary.initial_cost / n),
                std::sqrt(2 * summary.final_cost / n),
                static_cast<int>(summary.iterations.size()) - 1, summary.total_time_in_seconds,
                summary.message.c_str());
    if (!report_path.empty()) {
      nlohmann::ordered_json j;
      j["input"] = input;
      j["solver"] = "ceres " + solver;
      j["num_cameras"] = p.num_cameras();
      j["num_points"] = p.num_points();
      j["num_observations"] = p.num_observations();
      j["threads"] = threads;
      j["initial_cost"] = summary.initial_cost;
      j["final_cost"] = summary.final_cost;
      j["initial_rms_px"] = std::sqrt(2 * summary.initial_cost / n);
      j["final_rms_px"] = std::sqrt(2 * summary.final_cost / n);
      j["iterations"] = static_cast<int>(summary.iterations.size()) - 1;
      j["termination"] = ceres::TerminationTypeToString(summary.termination_type);
      j["termination_message"] = summary.message;
      j["seconds"] = {{"preprocessor", summary.preprocessor_time_in_seconds},
                      {"minimizer", summary.minimizer_time_in_seconds},
                      {"total", summary.total_time_in_seconds}};
      j["history"] = history.entries;
      dba::WriteFileAtomically(report_path, j.dump(2) + "\n");
    }
    return summary.IsSolutionUsable() ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "ceres_bal: error: " << e.what() << "\n";
    return 1;
  }
}
