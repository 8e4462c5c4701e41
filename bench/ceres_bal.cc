// Ceres baseline for the comparison benchmarks: solves a BAL problem
// with Ceres's public API and the standard BAL reprojection model (the same as
// dba's, data/README.md), and writes a JSON report with the keys of
// `dba solve --report`. It builds against Ceres 2.1 (Debian's libceres-dev)
// and 2.2 (../shared/peers/ceres-2.2.0/build.sh) alike; bench/compare.sh
// builds one binary against each. It needs no version checks: of the API
// that changed in 2.2 (LocalParameterization removed for Manifold, among
// others) it uses nothing; CERES_VERSION_STRING goes into the report.
//
//   ceres_bal INPUT [--solver iterative_schur|sparse_schur|dense_schur] [-t N]
//             [--max-iterations N] [--function-tolerance X]
//             [--eta X] [--max-linear-iterations N] [--report FILE]
//             [--loss trivial|huber|soft_l1|cauchy|arctan|tukey] [--loss-scale A]
//   ceres_bal --version      the Ceres version it was built against
//
// INPUT is BAL text (plain or bzip2) or a dba binary problem, read with dba's
// reader so both programs load the same data the same way. A photogrammetric
// .dba (RADIAL groups; dba generate --model photo) is solved with its shared
// intrinsics, the principal point held as dba's default holds it; with rigs
// (.dba version 4) each observation's pose is its frame's after its sensor's
// (origin sensors the identity, held sensors constant), as dba solves it.
//
// Solver: ITERATIVE_SCHUR + SCHUR_JACOBI by default (the configuration the
// paper compares with), SPARSE_SCHUR with --solver sparse_schur (Ceres's
// default sparse library, SuiteSparse here), DENSE_SCHUR with --solver
// dense_schur (Ceres's default dense library, Eigen; for a few hundred
// cameras at most). Points are eliminated first (explicit ordering, as in
// Ceres's bundle_adjuster example).
// Everything else is Ceres's default, which matches dba's defaults: initial
// trust region radius 1e4 (λ = 1e-4), gradient tolerance 1e-10, parameter
// tolerance 1e-8, at most 500 linear iterations; Ceres's inexact Newton
// forcing term eta = 0.1 (CG stops at a relative residual of 0.1) applies to
// ITERATIVE_SCHUR only, and --eta changes it.
//
// Report: the keys of `dba solve --report` that both programs can fill
// (initial_cost, final_cost, *_rms_px, iterations, termination by dba's names,
// seconds.{load,total}, memory.peak_bytes; seconds.total = load + building the
// ceres::Problem + Solve), `solver` ("ceres " + the --solver name),
// `ceres_version`, and `history`: one entry per Ceres
// iteration (0 = the initial state) with `cost` at the END of the iteration
// (dba's history gives the cost at its start and `candidate_cost`),
// `seconds` of the iteration and `cumulative_seconds` since Solve was called
// (add seconds.load and seconds.build_problem for the time since start).
// Cost is ½ Σ |r|², as in dba.
#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dba/io/atomic_output_file.h"
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

// The photogrammetric model's RADIAL lens (f, cx, cy, k1, k2; dba's
// camera/lens_projection.h): n = P.xy / P.z, u = f (1 + k1 r² + k2 r⁴) n + c.
template <typename T>
void RadialResidual(const T* P, const T* k, double x, double y, T* residual) {
  const T nx = P[0] / P[2], ny = P[1] / P[2];
  const T r2 = nx * nx + ny * ny;
  const T d = T(1.0) + r2 * (k[3] + k[4] * r2);
  residual[0] = k[0] * d * nx + k[1] - T(x);
  residual[1] = k[0] * d * ny + k[2] - T(y);
}

// An image's pose (ω, t), P = R(ω) X + t.
struct RadialImageError {
  RadialImageError(double x, double y) : x(x), y(y) {}
  template <typename T>
  bool operator()(const T* pose, const T* k, const T* point, T* residual) const {
    T P[3];
    ceres::AngleAxisRotatePoint(pose, point, P);
    for (int a = 0; a < 3; ++a) P[a] += pose[3 + a];
    RadialResidual(P, k, x, y, residual);
    return true;
  }
  double x, y;
};

// A rig's image: its sensor's pose after its frame's (docs/design.md §1.7),
// P = R_s (R_f X + t_f) + t_s.
struct RadialRigError {
  RadialRigError(double x, double y) : x(x), y(y) {}
  template <typename T>
  bool operator()(const T* frame, const T* sensor, const T* k, const T* point, T* residual) const {
    T Q[3], P[3];
    ceres::AngleAxisRotatePoint(frame, point, Q);
    for (int a = 0; a < 3; ++a) Q[a] += frame[3 + a];
    ceres::AngleAxisRotatePoint(sensor, Q, P);
    for (int a = 0; a < 3; ++a) P[a] += sensor[3 + a];
    RadialResidual(P, k, x, y, residual);
    return true;
  }
  double x, y;
};

// The photogrammetric problem (RADIAL groups only) in `problem`: per
// observation the image's pose (with rigs its frame's and sensor's), its
// group's intrinsics with dba's defaults (the principal point held, and
// what the file holds), the point; cameras and frames after the points.
void AddPhotoProblem(dba::Problem& p, ceres::LossFunction* loss, ceres::Problem* problem,
                     ceres::ParameterBlockOrdering* ordering) {
  for (int64_t g = 0; g < p.num_groups(); ++g) {
    if (p.group_model(g) != dba::LensModel::kRadial) {
      throw std::invalid_argument("intrinsic group " + std::to_string(g) +
                                  ": only the RADIAL lens model is written out here");
    }
  }
  const bool rigs = p.has_rigs();
  for (int64_t k = 0; k < p.num_points(); ++k) {
    for (int64_t o = p.point_offsets[k]; o < p.point_offsets[k + 1]; ++o) {
      const int64_t i = p.obs_camera[o];
      const int64_t g = p.camera_intrinsics[i];
      const double x = p.obs_pixel[2 * o], y = p.obs_pixel[2 * o + 1];
      if (rigs && p.sensor_kind[g] != dba::kRigOrigin) {
        auto* cost = new ceres::AutoDiffCostFunction<RadialRigError, 2, 6, 6, 5, 3>(
            new RadialRigError(x, y));
        problem->AddResidualBlock(cost, loss, p.cameras.data() + p.frame_offset(p.image_frame[i]),
                                  p.cameras.data() + p.sensor_offset(g), p.intrinsics(g), p.point(k));
      } else {
        auto* cost = new ceres::AutoDiffCostFunction<RadialImageError, 2, 6, 5, 3>(
            new RadialImageError(x, y));
        double* pose = rigs ? p.cameras.data() + p.frame_offset(p.image_frame[i]) : p.camera(i);
        problem->AddResidualBlock(cost, loss, pose, p.intrinsics(g), p.point(k));
      }
    }
    ordering->AddElementToGroup(p.point(k), 0);
  }
  for (int64_t g = 0; g < p.num_groups(); ++g) {
    const uint16_t fixed = (p.fixed_intrinsics.empty() ? 0 : p.fixed_intrinsics[g]) |
                           dba::kIntrinsicCx | dba::kIntrinsicCy;
    std::vector<int> held;
    for (int j = 0; j < 5; ++j) {
      if (fixed & (1u << j)) held.push_back(j);
    }
    if (!problem->HasParameterBlock(p.intrinsics(g))) continue;
    ordering->AddElementToGroup(p.intrinsics(g), 1);
    if (held.size() == 5) {
      problem->SetParameterBlockConstant(p.intrinsics(g));
    } else {
      problem->SetManifold(p.intrinsics(g), new ceres::SubsetManifold(5, held));
    }
    if (!rigs || p.sensor_kind[g] == dba::kRigOrigin) continue;
    double* sensor = p.cameras.data() + p.sensor_offset(g);
    if (!problem->HasParameterBlock(sensor)) continue;
    ordering->AddElementToGroup(sensor, 1);
    if (p.sensor_kind[g] == dba::kSensorHeld) problem->SetParameterBlockConstant(sensor);
  }
  const int64_t poses = rigs ? p.num_frames() : p.num_images();
  std::vector<uint8_t> fixed(poses, 0);
  for (int64_t i = 0; i < p.num_images(); ++i) {
    if (p.camera_fixed(i)) fixed[rigs ? p.image_frame[i] : i] = 1;
  }
  for (int64_t f = 0; f < poses; ++f) {
    double* pose = rigs ? p.cameras.data() + p.frame_offset(f) : p.camera(f);
    if (!problem->HasParameterBlock(pose)) continue;
    ordering->AddElementToGroup(pose, 1);
    if (fixed[f]) problem->SetParameterBlockConstant(pose);
  }
}

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

// Ceres's reason for stopping, by the names dba's report uses.
std::string TerminationName(const ceres::Solver::Summary& s) {
  const std::string& m = s.message;
  if (m.rfind("Function tolerance", 0) == 0) return "function_tolerance";
  if (m.rfind("Gradient tolerance", 0) == 0) return "gradient_tolerance";
  if (m.rfind("Parameter tolerance", 0) == 0) return "parameter_tolerance";
  if (m.rfind("Maximum number of iterations", 0) == 0) return "max_iterations";
  return std::string("ceres_") + ceres::TerminationTypeToString(s.termination_type);
}

int64_t PeakRssBytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<int64_t>(u.ru_maxrss) * 1024;  // Linux: KiB
}

int Usage() {
  std::cerr << "Usage: ceres_bal INPUT [--solver iterative_schur|sparse_schur|dense_schur]\n"
               "                 [-t N] [--max-iterations N] [--function-tolerance X]\n"
               "                 [--eta X] [--max-linear-iterations N] [--report FILE]\n"
               "                 [--loss trivial|huber|soft_l1|cauchy|arctan|tukey] [--loss-scale A]\n"
               "       ceres_bal --version\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string input, report_path, solver = "iterative_schur";
  int threads = 2, max_iterations = 100, max_linear_iterations = 500;
  double function_tolerance = 1e-6, eta = 0.1, loss_scale = 1.0;
  std::string loss_name = "trivial";
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
      else if (a == "--eta") eta = std::stod(value());
      else if (a == "--max-linear-iterations") max_linear_iterations = std::stoi(value());
      else if (a == "--report") report_path = value();
      else if (a == "--loss") loss_name = value();
      else if (a == "--loss-scale") loss_scale = std::stod(value());
      else if (a == "-h" || a == "--help") { Usage(); return 0; }
      else if (a == "--version") { std::printf("%s\n", CERES_VERSION_STRING); return 0; }
      else if (!a.empty() && a[0] == '-') return Usage();
      else input = a;
    } catch (const std::exception& e) {
      std::cerr << "ceres_bal: " << a << ": " << e.what() << "\n";
      return Usage();
    }
  }
  if (input.empty()) return Usage();
  // Ceres's own losses, the same definitions as dba's --loss.
  auto make_loss = [&]() -> ceres::LossFunction* {
    if (loss_name == "huber") return new ceres::HuberLoss(loss_scale);
    if (loss_name == "soft_l1") return new ceres::SoftLOneLoss(loss_scale);
    if (loss_name == "cauchy") return new ceres::CauchyLoss(loss_scale);
    if (loss_name == "arctan") return new ceres::ArctanLoss(loss_scale);
    if (loss_name == "tukey") return new ceres::TukeyLoss(loss_scale);
    return nullptr;
  };
  // One loss for all residual blocks, owned here (not a copy per block).
  const std::unique_ptr<ceres::LossFunction> loss(make_loss());
  if (loss_name != "trivial" && loss == nullptr) {
    std::cerr << "ceres_bal: unknown loss '" << loss_name << "'\n";
    return Usage();
  }
  if (solver != "iterative_schur" && solver != "sparse_schur" && solver != "dense_schur") {
    std::cerr << "ceres_bal: unknown solver '" << solver << "'\n";
    return Usage();
  }
  try {
    const auto t0 = std::chrono::steady_clock::now();
    dba::Problem p = dba::ReadProblem(input);
    const double load_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    const auto t1 = std::chrono::steady_clock::now();
    ceres::Problem::Options problem_options;
    problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    if (p.model == dba::CameraModel::kPhoto) AddPhotoProblem(p, loss.get(), &problem, ordering.get());
    for (int64_t k = 0; p.model == dba::CameraModel::kBal && k < p.num_points(); ++k) {
      for (int64_t o = p.point_offsets[k]; o < p.point_offsets[k + 1]; ++o) {
        auto* cost = new ceres::AutoDiffCostFunction<BalReprojectionError, 2, 9, 3>(
            new BalReprojectionError(p.obs_pixel[2 * o], p.obs_pixel[2 * o + 1]));
        problem.AddResidualBlock(cost, loss.get(), p.camera(p.obs_camera[o]), p.point(k));
      }
      ordering->AddElementToGroup(p.point(k), 0);
    }
    for (int64_t i = 0; p.model == dba::CameraModel::kBal && i < p.num_images(); ++i) {
      ordering->AddElementToGroup(p.camera(i), 1);
    }
    const double build_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();

    ceres::Solver::Options options;
    if (solver == "iterative_schur") {
      options.linear_solver_type = ceres::ITERATIVE_SCHUR;
      options.preconditioner_type = ceres::SCHUR_JACOBI;
    } else if (solver == "sparse_schur") {
      options.linear_solver_type = ceres::SPARSE_SCHUR;
    } else {
      options.linear_solver_type = ceres::DENSE_SCHUR;
    }
    options.linear_solver_ordering = ordering;
    options.num_threads = threads;
    options.max_num_iterations = max_iterations;
    options.function_tolerance = function_tolerance;
    options.eta = eta;
    options.max_linear_solver_iterations = max_linear_iterations;
    options.minimizer_progress_to_stdout = false;
    History history;
    options.callbacks.push_back(&history);
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);

    const double n = static_cast<double>(p.num_observations());
    const int iterations = static_cast<int>(summary.iterations.size()) - 1;
    const double total_seconds = load_seconds + build_seconds + summary.total_time_in_seconds;
    std::printf("ceres_bal %s (Ceres %s %s, %d threads): cost %.6e -> %.6e, RMS %.4f -> %.4f px, "
                "%d iterations, %.3f s (load %.3f s), %s\n",
                input.c_str(), CERES_VERSION_STRING, solver.c_str(), threads, summary.initial_cost,
                summary.final_cost, std::sqrt(2 * summary.initial_cost / n),
                std::sqrt(2 * summary.final_cost / n), iterations, total_seconds,
                load_seconds, summary.message.c_str());
    if (!report_path.empty()) {
      nlohmann::ordered_json j;
      j["input"] = input;
      j["solver"] = "ceres " + solver;
      j["ceres_version"] = CERES_VERSION_STRING;
      j["num_cameras"] = p.num_images();
      j["num_points"] = p.num_points();
      j["num_observations"] = p.num_observations();
      j["threads"] = threads;
      j["initial_cost"] = summary.initial_cost;
      j["final_cost"] = summary.final_cost;
      j["initial_rms_px"] = std::sqrt(2 * summary.initial_cost / n);
      j["final_rms_px"] = std::sqrt(2 * summary.final_cost / n);
      j["iterations"] = iterations;
      j["accepted_iterations"] = summary.num_successful_steps;
      j["linear_solver_iterations"] = [&] {
        int64_t s = 0;
        for (const auto& it : summary.iterations) s += it.linear_solver_iterations;
        return s;
      }();
      j["termination"] = TerminationName(summary);
      j["termination_message"] = summary.message;
      j["ceres_termination"] = ceres::TerminationTypeToString(summary.termination_type);
      j["eta"] = eta;
      j["seconds"] = {{"load", load_seconds},
                      {"build_problem", build_seconds},
                      {"preprocessor", summary.preprocessor_time_in_seconds},
                      {"minimizer", summary.minimizer_time_in_seconds},
                      {"linear_solver", summary.linear_solver_time_in_seconds},
                      {"jacobian_evaluation", summary.jacobian_evaluation_time_in_seconds},
                      {"residual_evaluation", summary.residual_evaluation_time_in_seconds},
                      {"postprocessor", summary.postprocessor_time_in_seconds},
                      {"total", total_seconds}};
      j["memory"] = {{"peak_bytes", PeakRssBytes()},
                     {"peak_bytes_per_observation", PeakRssBytes() / std::max(n, 1.0)}};
      j["history"] = history.entries;
      dba::WriteFileAtomically(report_path, j.dump(2) + "\n");
    }
    return summary.IsSolutionUsable() ? 0 : 1;
  } catch (const std::exception& e) {
    std::cerr << "ceres_bal: error: " << e.what() << "\n";
    return 1;
  }
}
