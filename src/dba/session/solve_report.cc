// Human and JSON summaries of a solve; see solve_report.h.
#include "dba/session/solve_report.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <ostream>

namespace dba {
namespace {

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

nlohmann::ordered_json TrafficJson(const TrafficStats& t) {
  nlohmann::ordered_json j;
  for (int i = 0; i < kNumTraffic; ++i) {
    j[TrafficName(static_cast<Traffic>(i))] = {{"bytes", t.bytes[i]},
                                               {"seconds", t.seconds[i]},
                                               {"wait_seconds", t.wait_seconds[i]}};
  }
  j["total"] = {{"bytes", t.total_bytes()},
                {"seconds", t.total_seconds()},
                {"wait_seconds", t.total_wait_seconds()}};
  return j;
}

}  // namespace

double SolveReport::TotalSeconds() const {
  return load_seconds + solve.distribution_seconds + solve.ba.symbolic_seconds +
         solve.ba.lm.times.total + write_seconds;
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

void PrintSolveReport(const SolveReport& r, std::ostream& out) {
  const LmSummary& lm = r.solve.ba.lm;
  const RcsFootprint& rcs = r.solve.ba.rcs;
  const double per_obs = 1.0 / std::max<int64_t>(r.num_observations, 1);
  char buf[512];
  out << "\nSummary\n";
  // Initial figures over the loaded observations, final ones over those
  // left after outlier rejection.
  const double n0 = static_cast<double>(r.num_observations);
  const double n = static_cast<double>(lm.num_observations);
  if (r.loss.trivial()) {
    std::snprintf(buf, sizeof buf,
                  "  initial cost        %.6e  (RMS %.4f px)\n"
                  "  final cost          %.6e  (RMS %.4f px)\n",
                  lm.initial_cost, LmSummary::Rms(lm.initial_residuals.squared, n0), lm.final_cost,
                  LmSummary::Rms(lm.final_residuals.squared, n));
  } else {
    const ResidualSums &a = lm.initial_residuals, &b = lm.final_residuals;
    std::snprintf(buf, sizeof buf,
                  "  loss                %s, scale %g px (inliers: residual within the scale)\n"
                  "  initial cost        %.6e  (robust; RMS %.4f px, inliers %.4f px over %.2f%%)\n",
                  LossName(r.loss.type), r.loss.scale, lm.initial_cost,
                  LmSummary::Rms(a.squared, n0), LmSummary::Rms(a.inlier_squared, a.inliers),
                  n0 > 0 ? 100.0 * a.inliers / n0 : 0.0);
    out << buf;
    if (r.final_loss.trivial()) {
      std::snprintf(buf, sizeof buf,
                    "  final cost          %.6e  (squared loss after outlier rejection; RMS %.4f px)\n",
                    lm.final_cost, LmSummary::Rms(b.squared, n));
    } else {
      std::snprintf(buf, sizeof buf,
                    "  final cost          %.6e  (robust; RMS %.4f px, inliers %.4f px over %.2f%%)\n",
                    lm.final_cost, LmSummary::Rms(b.squared, n),
                    LmSummary::Rms(b.inlier_squared, b.inliers), n > 0 ? 100.0 * b.inliers / n : 0.0);
    }
  }
  out << buf;
  out << "  iterations          " << lm.iterations << " (" << lm.accepted_iterations
      << " accepted, " << lm.total_linear_iterations << " PCG iterations)\n";
  out << "  linear solver       " << LinearSolverName(lm.linear_solver.type) << " ("
      << lm.linear_solver.reason << "); holds " << Bytes(lm.linear_solver_bytes)
      << " beyond the RCS";
  if (lm.pcg_double_from_iteration > 0) {
    out << "; product in double from LM iteration " << lm.pcg_double_from_iteration
        << " (damping at float's floor)";
  }
  out << "\n";
  out << "  termination         " << TerminationReasonName(lm.termination) << ": "
      << lm.termination_message << "\n";
  std::snprintf(buf, sizeof buf,
                "  time (s)            load %.3f  distribute %.3f  setup %.3f  rcs %.3f  "
                "linear solve %.3f  back-substitution %.3f  write %.3f  total %.3f\n",
                r.load_seconds, r.solve.distribution_seconds, r.solve.ba.symbolic_seconds,
                lm.times.rcs_formation, lm.times.linear_solve, lm.times.back_substitution,
                r.write_seconds, r.TotalSeconds());
  out << buf;
  out << "  unknowns            " << rcs.camera_unknowns + 3 * r.num_points << " ("
      << rcs.camera_unknowns << " camera-side, " << 3 * r.num_points << " point coordinates)\n";
  out << "  RCS (BSMC)          " << rcs.block_rows << " block rows, " << rcs.blocks
      << " blocks, " << Bytes(rcs.bsmc_structure_bytes + rcs.bsmc_value_bytes)
      << " (CSR: " << Bytes(rcs.csr_bytes) << ")\n";
  std::snprintf(buf, sizeof buf,
                "  memory              peak %s, %.1f bytes/observation "
                "(problem data %.1f bytes/observation)\n",
                Bytes(r.peak_memory_bytes).c_str(), r.peak_memory_bytes * per_obs,
                r.problem_bytes * per_obs);
  out << buf;
  if (r.memory_estimate.total() > 0) {
    out << "  memory estimate     " << r.memory_estimate.Describe() << "\n";
  }
  if (!r.rejection.empty()) {
    int64_t obs = 0, points = 0;
    for (const RejectionRound& round : r.rejection) {
      obs += round.observations_dropped;
      points += round.points_dropped;
    }
    std::snprintf(buf, sizeof buf,
                  "  outlier rejection   |r| > %g px, %zu rounds: dropped %lld observations "
                  "(%.3f%%) and %lld points\n",
                  r.reject_outliers_px, r.rejection.size(), static_cast<long long>(obs),
                  100.0 * static_cast<double>(obs) * per_obs, static_cast<long long>(points));
    out << buf;
  }
  if (r.has_outlier_truth) {
    std::snprintf(buf, sizeof buf,
                  "  true outliers       %lld of %lld dropped (%.2f%%); true inliers dropped "
                  "%lld of %lld (%.3f%%)\n",
                  static_cast<long long>(r.true_outliers_dropped),
                  static_cast<long long>(r.true_outliers),
                  r.true_outliers ? 100.0 * r.true_outliers_dropped / r.true_outliers : 0.0,
                  static_cast<long long>(r.true_inliers_dropped),
                  static_cast<long long>(r.true_inliers),
                  r.true_inliers ? 100.0 * r.true_inliers_dropped / r.true_inliers : 0.0);
    out << buf;
  }
  if (r.geo.has_priors || r.geo.has_ground_control) {
    const AccuracyReport& a = r.geo.accuracy;
    // One line of figures per set.
    auto figures = [&](const char* label, const AccuracyFigures& f, const char* what) {
      std::snprintf(buf, sizeof buf,
                    "  %-19s %lld; %s (m): mean X %.4g Y %.4g Z %.4g, sd %.4g %.4g "
                    "%.4g, RMS %.4g %.4g %.4g, 3D %.4g; CE90 %.4g, LE90 %.4g\n",
                    label, static_cast<long long>(f.count), what, f.mean[0], f.mean[1], f.mean[2],
                    f.sd[0], f.sd[1], f.sd[2], f.rms[0], f.rms[1], f.rms[2], f.rms_3d, f.ce90,
                    f.le90);
      out << buf;
    };
    if (r.geo.has_priors) figures("camera priors", a.gnss.figures, "C - prior");
    if (r.geo.has_ground_control) {
      figures("control points", a.control.figures, "X - survey");
      figures("check points", a.check.figures, "triangulated - survey");
      if (!r.geo.check_points_not_triangulated.empty()) {
        out << "  not triangulated   ";
        for (const std::string& n : r.geo.check_points_not_triangulated) out << " " << n;
        out << "\n";
      }
    }
    if (r.geo.has_local_frame) {
      std::snprintf(buf, sizeof buf,
                    "  local frame         ENU at %.9f, %.9f, %.3f m (WGS84 φ, λ, h); in %s "
                    "(%s heights)\n",
                    r.geo.local_frame_origin.x(), r.geo.local_frame_origin.y(), r.geo.local_frame_origin.z(),
                    r.geo.prior_crs.c_str(), r.geo.prior_heights.c_str());
      out << buf << "  PROJ pipeline       " << r.geo.local_frame_pipeline << "\n";
    }
    std::snprintf(buf, sizeof buf, "  unit weight         σ0² %.4g (%lld degrees of freedom)\n",
                  a.sigma0_squared, static_cast<long long>(a.degrees_of_freedom));
    out << buf;
    auto flagged = [&](const char* label, const AccuracyFigures& f) {
      std::string names;
      for (size_t k = 0; k < f.flagged.size() && k < 10; ++k) names += " " + f.flagged[k];
      if (f.flagged.size() > 10) names += " ...";
      out << label << f.flagged.size() << " (squared Mahalanobis distance > 16.27)"
          << (names.empty() ? "" : ":" + names) << "\n";
    };
    if (r.geo.has_priors) flagged("  priors flagged      ", a.gnss.figures);
    if (r.geo.has_ground_control) flagged("  control flagged     ", a.control.figures);
  }
  if (r.has_truth && r.truth.absolute) {
    std::snprintf(buf, sizeof buf,
                  "  ground truth        RMS to noise-free observations %.4f px; absolute (no\n"
                  "                      alignment): camera centres %.4g, points %.4g (RMS)\n",
                  r.truth.rms_to_noise_free_px, r.truth.camera_centre_rms, r.truth.point_rms);
    out << buf;
  } else if (r.has_truth) {
    std::snprintf(buf, sizeof buf,
                  "  ground truth        RMS to noise-free observations %.4f px; after a\n"
                  "                      similarity (scale %.6f): camera centres %.4g, points %.4g (RMS)\n",
                  r.truth.rms_to_noise_free_px, r.truth.similarity_scale,
                  r.truth.camera_centre_rms, r.truth.point_rms);
    out << buf;
  }
  if (r.has_truth) {
    if (r.truth.mismatches_left_out > 0) {
      std::snprintf(buf, sizeof buf,
                    "                      (the RMS over %lld true inliers; %lld generated "
                    "mismatches left out)\n",
                    static_cast<long long>(r.truth.rms_observations),
                    static_cast<long long>(r.truth.mismatches_left_out));
      out << buf;
    }
    // Intrinsic groups (photogrammetric model): each, or the worst of many
    // (per parameter, named after the first group's model).
    const auto& err = r.truth.intrinsics_error;
    const auto line = [&](const std::string& what, LensModel m, const std::vector<double>& e,
                          double focal_relative) {
      std::string s = "  intrinsics " + what + " error";
      for (size_t j = 0; j < e.size(); ++j) {
        std::snprintf(buf, sizeof buf, "%s %s %.4g", j == 0 ? "" : ",",
                      LensModelParamName(m, static_cast<int>(j)).c_str(), e[j]);
        s += buf;
        if (j == 0) {
          std::snprintf(buf, sizeof buf, " (%.3g %%)", 100.0 * focal_relative);
          s += buf;
        }
      }
      out << s << "\n";
    };
    const size_t shown = err.size() <= 8 ? err.size() : 0;
    for (size_t g = 0; g < shown; ++g) {
      std::snprintf(buf, sizeof buf, "%-8zu", g);
      line(buf, r.truth.intrinsics_model[g], err[g], err[g][0] / r.truth.true_focal[g]);
    }
    if (err.size() > shown) {
      std::vector<double> worst(err[0].size(), 0.0);
      double worst_f = 0.0;
      for (size_t g = 0; g < err.size(); ++g) {
        for (size_t j = 0; j < std::min(worst.size(), err[g].size()); ++j) {
          worst[j] = std::max(worst[j], err[g][j]);
        }
        worst_f = std::max(worst_f, err[g][0] / r.truth.true_focal[g]);
      }
      line("(" + std::to_string(err.size()) + " groups) largest", r.truth.intrinsics_model[0],
           worst, worst_f);
    }
  }
  if (r.solve.ranks > 1) {
    const TrafficStats& t = r.solve.traffic;
    out << "  ranks               " << r.solve.ranks << " ("
        << PartitionSchemeName(r.solve.partition) << " partition, main rank "
        << (r.solve.main_forms ? "forms a sub-RCS" : "coordinates only") << ", RCS "
        << (r.solve.rcs == RcsPlacement::kDistributed ? "spread over the ranks" : "gathered on rank 0")
        << ")\n";
    for (const RankReport& k : r.solve.rank_reports) {
      std::snprintf(buf, sizeof buf,
                    "    rank %-3d  %10ld points %11ld observations %7ld cameras  "
                    "sub-RCS %8ld blocks %10s  peak %s (estimated %s)\n",
                    k.rank, static_cast<long>(k.points), static_cast<long>(k.observations),
                    static_cast<long>(k.cameras), static_cast<long>(k.sub_rcs_blocks),
                    Bytes(k.sub_rcs_bytes).c_str(), Bytes(k.peak_memory_bytes).c_str(),
                    Bytes(k.memory_estimate_bytes).c_str());
      out << buf;
      if (r.solve.rcs == RcsPlacement::kDistributed) {
        const TrafficStats& kt = k.traffic;
        auto at = [&](Traffic c) { return static_cast<int>(c); };
        std::snprintf(buf, sizeof buf,
                      "              owns %ld RCS rows, %ld blocks, %s with its solve (halo %ld "
                      "rows); reduce-scatter %s %.3f s, halo %s %.3f s, reductions %s %.3f s\n",
                      static_cast<long>(k.owned_rows), static_cast<long>(k.owned_blocks),
                      Bytes(k.owned_bytes).c_str(), static_cast<long>(k.halo_rows),
                      Bytes(kt.bytes[at(Traffic::kSubRcs)]).c_str(), kt.seconds[at(Traffic::kSubRcs)],
                      Bytes(kt.bytes[at(Traffic::kHalo)]).c_str(), kt.seconds[at(Traffic::kHalo)],
                      Bytes(kt.bytes[at(Traffic::kReduction)]).c_str(),
                      kt.seconds[at(Traffic::kReduction)]);
        out << buf;
      }
    }
    const double iters = std::max<size_t>(r.solve.per_iteration.size(), 1);
    out << "  communication (main rank, sent + received; waits for other ranks apart)\n";
    for (Traffic c : {Traffic::kDistribution, Traffic::kSubRcs, Traffic::kCameraUpdate,
                      Traffic::kControl, Traffic::kResult, Traffic::kHalo,
                      Traffic::kReduction}) {
      const int i = static_cast<int>(c);
      std::snprintf(buf, sizeof buf,
                    "    %-14s %12s %9.3f s  (waits %8.3f s)  per iteration %10s %8.4f s\n",
                    TrafficName(c), Bytes(t.bytes[i]).c_str(), t.seconds[i], t.wait_seconds[i],
                    Bytes(static_cast<int64_t>(t.bytes[i] / iters)).c_str(),
                    t.seconds[i] / iters);
      out << buf;
    }
    std::snprintf(buf, sizeof buf,
                  "    %-14s %12s %9.3f s  (waits %8.3f s)  transfers are %.1f%% of the solve\n",
                  "total", Bytes(t.total_bytes()).c_str(), t.total_seconds(),
                  t.total_wait_seconds(),
                  100.0 * t.total_seconds() / std::max(r.TotalSeconds(), 1e-9));
    out << buf;
  }
}

std::string SolveReportJson(const SolveReport& r) {
  const LmSummary& lm = r.solve.ba.lm;
  const RcsFootprint& rcs = r.solve.ba.rcs;
  const double per_obs = 1.0 / std::max<int64_t>(r.num_observations, 1);
  nlohmann::ordered_json j;
  j["input"] = r.input;
  j["num_cameras"] = r.num_cameras;
  j["num_intrinsic_groups"] = r.num_intrinsic_groups;
  j["camera_unknowns"] = rcs.camera_unknowns;
  j["unknowns"] = rcs.camera_unknowns + 3 * r.num_points;
  j["num_points"] = r.num_points;
  j["num_observations"] = r.num_observations;
  j["threads"] = r.threads;
  j["ranks"] = r.solve.ranks;
  j["initial_cost"] = lm.initial_cost;
  j["final_cost"] = lm.final_cost;
  const double n0 = static_cast<double>(r.num_observations);
  const double n = static_cast<double>(lm.num_observations);
  j["loss"] = {{"type", LossName(r.loss.type)}, {"scale_px", r.loss.scale}};
  // The loss of final_cost (the squared loss after outlier rejection unless
  // --reject-keep-loss).
  j["final_loss"] = {{"type", LossName(r.final_loss.type)}, {"scale_px", r.final_loss.scale}};
  // Costs are the robust ½ Σ ρ(|r|²); RMS figures are of the plain residuals,
  // over all observations and over the inliers (|r| within the loss scale;
  // all, for the trivial loss).
  j["initial_rms_px"] = LmSummary::Rms(lm.initial_residuals.squared, n0);
  j["final_rms_px"] = LmSummary::Rms(lm.final_residuals.squared, n);
  j["initial_inliers"] = static_cast<int64_t>(lm.initial_residuals.inliers);
  j["final_inliers"] = static_cast<int64_t>(lm.final_residuals.inliers);
  j["initial_inlier_rms_px"] =
      LmSummary::Rms(lm.initial_residuals.inlier_squared, lm.initial_residuals.inliers);
  j["final_inlier_rms_px"] =
      LmSummary::Rms(lm.final_residuals.inlier_squared, lm.final_residuals.inliers);
  j["iterations"] = lm.iterations;
  j["accepted_iterations"] = lm.accepted_iterations;
  j["pcg_iterations"] = lm.total_linear_iterations;
  j["linear_solver"] = {{"type", LinearSolverName(lm.linear_solver.type)},
                        {"reason", lm.linear_solver.reason},
                        {"bytes", lm.linear_solver_bytes},
                        {"pcg_double_from_iteration", lm.pcg_double_from_iteration},
                        {"pcg_path_bytes", lm.linear_solver.pcg_bytes},
                        {"factor_budget_bytes", lm.linear_solver.budget_bytes},
                        {"dense_factor_bytes", lm.linear_solver.dense_bytes},
                        {"sparse_factor_bytes_estimate", lm.linear_solver.sparse_bytes},
                        {"estimated_seconds",
                         {{"pcg", lm.linear_solver.estimated_pcg_seconds},
                          {"dense", lm.linear_solver.estimated_dense_seconds},
                          {"sparse", lm.linear_solver.estimated_sparse_seconds}}}};
  j["termination"] = TerminationReasonName(lm.termination);
  j["termination_message"] = lm.termination_message;
  j["seconds"] = {{"load", r.load_seconds},
                  {"distribution", r.solve.distribution_seconds},
                  {"setup", r.solve.ba.symbolic_seconds},
                  {"rcs_formation", lm.times.rcs_formation},
                  {"linear_solve", lm.times.linear_solve},
                  {"back_substitution", lm.times.back_substitution},
                  {"write", r.write_seconds},
                  {"total", r.TotalSeconds()}};
  j["memory"] = {{"peak_bytes", r.peak_memory_bytes},
                 {"peak_bytes_per_observation", r.peak_memory_bytes * per_obs},
                 {"problem_bytes", r.problem_bytes},
                 {"rcs_bsmc_structure_bytes", rcs.bsmc_structure_bytes},
                 {"rcs_bsmc_value_bytes", rcs.bsmc_value_bytes},
                 {"rcs_csr_bytes", rcs.csr_bytes},
                 {"rcs_blocks", rcs.blocks}};
  if (r.memory_estimate.total() > 0) {
    const MemoryEstimate& e = r.memory_estimate;
    j["memory"]["estimate"] = {{"total_bytes", e.total()},
                               {"process_bytes", e.resident},
                               {"peak_so_far_bytes", e.peak_so_far},
                               {"rcs_bytes", e.rcs},
                               {"formation_bytes", e.formation},
                               {"lm_bytes", e.lm},
                               {"candidate_points_bytes", e.candidate},
                               {"linear_solver_bytes", e.linear_solver},
                               {"linear_solver", LinearSolverName(e.solver)},
                               {"available_bytes", r.available_memory_bytes}};
  }
  if (r.reject_outliers_px > 0) {
    nlohmann::ordered_json rounds = nlohmann::ordered_json::array();
    for (const RejectionRound& round : r.rejection) {
      rounds.push_back({{"observations_dropped", round.observations_dropped},
                        {"points_dropped", round.points_dropped},
                        {"points_dropped_for_angle", round.points_small_angle},
                        {"observations_left", round.observations_left},
                        {"points_left", round.points_left}});
    }
    j["outlier_rejection"] = {{"max_error_px", r.reject_outliers_px}, {"rounds", rounds}};
  }
  if (r.has_outlier_truth) {
    j["true_outliers"] = {{"outliers", r.true_outliers},
                          {"outliers_dropped", r.true_outliers_dropped},
                          {"inliers", r.true_inliers},
                          {"inliers_dropped", r.true_inliers_dropped}};
  }
  auto figures_json = [](const AccuracyFigures& f) {
    return nlohmann::ordered_json{{"count", f.count}, {"mean", f.mean},     {"sd", f.sd},
                          {"rms", f.rms},     {"rms_3d", f.rms_3d}, {"ce90", f.ce90},
                          {"le90", f.le90},   {"flagged", f.flagged}};
  };
  const AccuracyReport& a = r.geo.accuracy;
  if (r.geo.has_priors || r.geo.has_ground_control) {
    j["georeferencing"] = {{"sigma0_squared", a.sigma0_squared},
                           {"degrees_of_freedom", a.degrees_of_freedom},
                           {"crs", r.geo.prior_crs},
                           {"heights", r.geo.prior_heights},
                           {"local_frame",
                            {{"origin_latitude", r.geo.local_frame_origin.x()},
                             {"origin_longitude", r.geo.local_frame_origin.y()},
                             {"origin_height", r.geo.local_frame_origin.z()},
                             {"proj_pipeline", r.geo.local_frame_pipeline}}}};
  }
  if (r.geo.has_priors) {
    nlohmann::ordered_json p = figures_json(a.gnss.figures);
    p["sigma0_squared"] = a.sigma0_squared;
    p["degrees_of_freedom"] = a.degrees_of_freedom;
    p["crs"] = r.geo.prior_crs;
    p["heights"] = r.geo.prior_heights;
    p["local_frame"] = j["georeferencing"]["local_frame"];
    p["loss"] = {{"type", LossName(r.geo.prior_loss.type)}, {"scale", r.geo.prior_loss.scale}};
    j["camera_priors"] = p;
  }
  if (r.geo.has_ground_control) {
    j["control_points"] = figures_json(a.control.figures);
    j["check_points"] = figures_json(a.check.figures);
    j["check_points"]["not_triangulated"] = r.geo.check_points_not_triangulated;
  }
  if (r.has_truth) {
    j["ground_truth"] = {{"rms_to_noise_free_px", r.truth.rms_to_noise_free_px},
                         {"rms_observations", r.truth.rms_observations},
                         {"mismatches_left_out", r.truth.mismatches_left_out},
                         {"similarity_scale", r.truth.similarity_scale},
                         {"absolute", r.truth.absolute},
                         {"camera_centre_rms", r.truth.camera_centre_rms},
                         {"point_rms", r.truth.point_rms}};
    if (!r.truth.intrinsics_error.empty()) {
      nlohmann::ordered_json groups = nlohmann::ordered_json::array();
      for (size_t g = 0; g < r.truth.intrinsics_error.size(); ++g) {
        const auto& e = r.truth.intrinsics_error[g];
        const LensModel m = r.truth.intrinsics_model[g];
        nlohmann::ordered_json group = {{"group", g},
                                        {"model", Info(m).name},
                                        {"f_relative", e[0] / r.truth.true_focal[g]}};
        for (size_t p = 0; p < e.size(); ++p) {
          group[LensModelParamName(m, static_cast<int>(p))] = e[p];
        }
        groups.push_back(std::move(group));
      }
      j["ground_truth"]["intrinsics_error"] = groups;
    }
    // Per camera, for a top view of the errors (python3 -m dba.plot).
    j["ground_truth"]["cameras"] = {{"true_x", r.truth.centre_x},
                                    {"true_y", r.truth.centre_y},
                                    {"centre_error", r.truth.centre_error}};
  }
  if (r.solve.ranks > 1) {
    nlohmann::ordered_json d;
    d["partition"] = PartitionSchemeName(r.solve.partition);
    d["rcs"] = RcsPlacementName(r.solve.rcs);
    d["main_rank_forms_sub_rcs"] = r.solve.main_forms;
    nlohmann::ordered_json ranks = nlohmann::ordered_json::array();
    for (const RankReport& k : r.solve.rank_reports) {
      ranks.push_back({{"rank", k.rank},
                       {"points", k.points},
                       {"observations", k.observations},
                       {"cameras", k.cameras},
                       {"sub_rcs_blocks", k.sub_rcs_blocks},
                       {"sub_rcs_bytes", k.sub_rcs_bytes},
                       {"peak_memory_bytes", k.peak_memory_bytes},
                       {"memory_estimate_bytes", k.memory_estimate_bytes},
                       {"traffic_bytes", k.traffic_bytes},
                       {"owned_rows", k.owned_rows},
                       {"owned_blocks", k.owned_blocks},
                       {"owned_bytes", k.owned_bytes},
                       {"halo_rows", k.halo_rows},
                       {"communication", TrafficJson(k.traffic)}});
      if (k.rank > 0 && k.rank < static_cast<int>(r.solve.rank_per_iteration.size())) {
        nlohmann::ordered_json per = nlohmann::ordered_json::array();
        for (const TrafficStats& t : r.solve.rank_per_iteration[k.rank]) per.push_back(TrafficJson(t));
        ranks.back()["communication_per_formation"] = per;
      }
    }
    d["ranks"] = ranks;
    d["communication"] = TrafficJson(r.solve.traffic);
    nlohmann::ordered_json per = nlohmann::ordered_json::array();
    for (const TrafficStats& t : r.solve.per_iteration) per.push_back(TrafficJson(t));
    d["communication_per_iteration"] = per;
    j["distributed"] = d;
  }
  nlohmann::ordered_json history = nlohmann::ordered_json::array();
  for (const IterationSummary& it : lm.history) {
    history.push_back({{"iteration", it.iteration},
                       {"cost", it.cost},
                       {"rms_px", it.rms_pixels},
                       {"gradient_max_norm", it.gradient_max_norm},
                       {"lambda", it.lambda},
                       {"linear_iterations", it.linear_iterations},
                       {"linear_relative_residual", it.linear_relative_residual},
                       {"linear_stop", it.linear_stop},
                       {"candidate_cost", it.candidate_cost},
                       {"gain_ratio", it.gain_ratio},
                       {"accepted", it.step_accepted},
                       {"seconds", it.seconds}});
  }
  j["history"] = history;
  return j.dump(2) + "\n";
}

}  // namespace dba
