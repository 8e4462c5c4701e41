// The printed summary of a solve: the summary value (SolveSummary, the
// --report JSON) rendered for people; no figure is computed here again.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>

#include "dba/common/memory.h"
#include "dba/session/solve_report.h"

namespace dba {
namespace {

using Json = nlohmann::ordered_json;

// printf into a string.
template <typename... A>
std::string Format(const char* format, A... args) {
  char buf[512];
  std::snprintf(buf, sizeof buf, format, args...);
  return buf;
}

double Percent(double part, double whole) { return whole > 0 ? 100.0 * part / whole : 0.0; }

void PrintCosts(const Json& j, std::ostream& out) {
  const double n0 = j["num_observations"], n = j["final_observations"];
  if (j["loss"]["type"] == "trivial") {
    out << Format("  initial cost        %.6e  (RMS %.4f px)\n"
                  "  final cost          %.6e  (RMS %.4f px)\n",
                  j["initial_cost"].get<double>(), j["initial_rms_px"].get<double>(),
                  j["final_cost"].get<double>(), j["final_rms_px"].get<double>());
    return;
  }
  out << Format("  loss                %s, scale %g px (inliers: residual within the scale)\n"
                "  initial cost        %.6e  (robust; RMS %.4f px, inliers %.4f px over %.2f%%)\n",
                j["loss"]["type"].get<std::string>().c_str(), j["loss"]["scale_px"].get<double>(),
                j["initial_cost"].get<double>(), j["initial_rms_px"].get<double>(),
                j["initial_inlier_rms_px"].get<double>(),
                Percent(j["initial_inliers"].get<double>(), n0));
  if (j["final_loss"]["type"] == "trivial") {
    out << Format("  final cost          %.6e  (squared loss after outlier rejection; RMS %.4f px)\n",
                  j["final_cost"].get<double>(), j["final_rms_px"].get<double>());
  } else {
    out << Format("  final cost          %.6e  (robust; RMS %.4f px, inliers %.4f px over %.2f%%)\n",
                  j["final_cost"].get<double>(), j["final_rms_px"].get<double>(),
                  j["final_inlier_rms_px"].get<double>(),
                  Percent(j["final_inliers"].get<double>(), n));
  }
}

// The wall time phase by phase from the run's start, in whole milliseconds,
// "other" the printed total's rest: the printed figures add up to the
// printed total exactly.
void PrintTimes(const Json& s, std::ostream& out) {
  struct Phase {
    const char *key, *label;
    bool ends_line;
  };
  static constexpr Phase kPhases[] = {
      {"startup", "start-up", false}, {"read", "read", false}, {"load", "checks", false},
      {"distribution", "distribute", false}, {"setup", "setup", true},
      {"rcs_formation", "rcs", false}, {"linear_solve", "linear solve", false},
      {"back_substitution", "back-substitution", false}, {"analysis", "analysis", false},
      {"write", "write", false}};
  const auto ms = [](double seconds) { return std::llround(1000.0 * seconds); };
  const long long total = ms(s["total"].get<double>());
  long long other = total;
  out << "  time (s)           ";
  for (const Phase& p : kPhases) {
    const long long t = ms(s[p.key].get<double>());
    other -= t;
    out << Format(" %s %.3f ", p.label, 0.001 * static_cast<double>(t))
        << (p.ends_line ? "\n                     " : "");
  }
  out << Format(" other %.3f  total %.3f (wall time from the start)\n",
                0.001 * static_cast<double>(other), 0.001 * static_cast<double>(total));
}

void PrintSolver(const Json& j, std::ostream& out) {
  const Json& ls = j["linear_solver"];
  out << "  iterations          " << j["iterations"].get<int>() << " ("
      << j["accepted_iterations"].get<int>() << " accepted, " << j["pcg_iterations"].get<int>()
      << " PCG iterations)\n";
  out << "  linear solver       " << ls["type"].get<std::string>() << " ("
      << ls["reason"].get<std::string>() << "); holds " << BytesText(ls["bytes"].get<double>())
      << " beyond the RCS";
  if (const int from = ls["pcg_double_from_iteration"]; from > 0) {
    out << "; product in double from LM iteration " << from << " (damping at float's floor)";
  }
  out << "\n  termination         " << j["termination"].get<std::string>() << ": "
      << j["termination_message"].get<std::string>() << "\n";
  PrintTimes(j["seconds"], out);
}

void PrintSizes(const Json& j, std::ostream& out) {
  const int64_t camera = j["camera_unknowns"], points = j["num_points"];
  const Json& m = j["memory"];
  out << "  unknowns            " << j["unknowns"].get<int64_t>() << " (" << camera
      << " camera-side, " << 3 * points << " point coordinates)\n";
  if (j.contains("camera_unknowns_by_kind") && !j["camera_unknowns_by_kind"].empty()) {
    std::string kinds;
    for (const auto& [kind, n] : j["camera_unknowns_by_kind"].items()) {
      std::string name = kind;
      std::replace(name.begin(), name.end(), '_', ' ');
      kinds += (kinds.empty() ? "" : ", ") + std::to_string(n.get<int64_t>()) + " in " + name;
    }
    out << "  camera-side         " << kinds << "\n";
  }
  out << "  RCS (BSMC)          " << m["rcs_block_rows"].get<int64_t>() << " block rows, "
      << m["rcs_blocks"].get<int64_t>() << " blocks, "
      << BytesText(m["rcs_bsmc_structure_bytes"].get<double>() + m["rcs_bsmc_value_bytes"].get<double>())
      << " (CSR: " << BytesText(m["rcs_csr_bytes"].get<double>()) << ")\n";
  out << Format("  memory              peak %s, %.1f bytes/observation "
                "(problem data %.1f bytes/observation)\n",
                BytesText(m["peak_bytes"].get<double>()).c_str(),
                m["peak_bytes_per_observation"].get<double>(),
                m["problem_bytes_per_observation"].get<double>());
  if (m.contains("estimate")) {
    out << "  memory estimate     " << m["estimate"]["description"].get<std::string>() << "\n";
  }
}

void PrintRejection(const Json& j, std::ostream& out) {
  if (j.contains("outlier_rejection") && !j["outlier_rejection"]["rounds"].empty()) {
    const Json& rounds = j["outlier_rejection"]["rounds"];
    int64_t obs = 0, points = 0;
    for (const Json& round : rounds) {
      obs += round["observations_dropped"].get<int64_t>();
      points += round["points_dropped"].get<int64_t>();
    }
    out << Format("  outlier rejection   |r| > %g px, %zu rounds: dropped %lld observations "
                  "(%.3f%%) and %lld points\n",
                  j["outlier_rejection"]["max_error_px"].get<double>(), rounds.size(),
                  static_cast<long long>(obs),
                  Percent(static_cast<double>(obs), j["num_observations"].get<double>()),
                  static_cast<long long>(points));
  }
  if (j.contains("true_outliers")) {
    const Json& t = j["true_outliers"];
    const double o = t["outliers"], od = t["outliers_dropped"], i = t["inliers"],
                 id = t["inliers_dropped"];
    out << Format("  true outliers       %lld of %lld dropped (%.2f%%); true inliers dropped "
                  "%lld of %lld (%.3f%%)\n",
                  static_cast<long long>(od), static_cast<long long>(o), Percent(od, o),
                  static_cast<long long>(id), static_cast<long long>(i), Percent(id, i));
  }
}

void PrintFigures(const char* label, const Json& f, const char* what, std::ostream& out) {
  const auto v = [&](const char* key, int a) { return f[key][a].get<double>(); };
  out << Format("  %-19s %lld; %s (m): mean X %.4g Y %.4g Z %.4g, sd %.4g %.4g %.4g, RMS %.4g "
                "%.4g %.4g, 3D %.4g; CE90 %.4g, LE90 %.4g\n",
                label, static_cast<long long>(f["count"].get<int64_t>()), what, v("mean", 0),
                v("mean", 1), v("mean", 2), v("sd", 0), v("sd", 1), v("sd", 2), v("rms", 0),
                v("rms", 1), v("rms", 2), f["rms_3d"].get<double>(), f["ce90"].get<double>(),
                f["le90"].get<double>());
}

void PrintFlagged(const char* label, const Json& f, std::ostream& out) {
  const Json& flagged = f["flagged"];
  std::string names;
  for (size_t k = 0; k < flagged.size() && k < 10; ++k) names += " " + flagged[k].get<std::string>();
  if (flagged.size() > 10) names += " ...";
  out << label << flagged.size() << " (squared Mahalanobis distance > 16.27)"
      << (names.empty() ? "" : ":" + names) << "\n";
}

void PrintGeoreferencing(const Json& j, std::ostream& out) {
  if (!j.contains("georeferencing")) return;
  const Json& g = j["georeferencing"];
  if (j.contains("camera_priors")) {
    const Json& p = j["camera_priors"];
    PrintFigures("camera priors", p, "antenna - prior", out);
    const Json& a = p["lever_arm"];
    out << Format("  lever arm           %.4f, %.4f, %.4f m (%s)\n", a[0].get<double>(),
                  a[1].get<double>(), a[2].get<double>(),
                  p["lever_arm_refined"].get<bool>() ? "refined" : "given");
  }
  if (j.contains("control_points")) {
    PrintFigures("control points", j["control_points"], "X - survey", out);
    PrintFigures("check points", j["check_points"], "triangulated - survey", out);
    const Json& missing = j["check_points"]["not_triangulated"];
    if (!missing.empty()) {
      out << "  not triangulated   ";
      for (const Json& n : missing) out << " " << n.get<std::string>();
      out << "\n";
    }
  }
  if (g["has_local_frame"].get<bool>()) {
    const Json& f = g["local_frame"];
    out << Format("  local frame         ENU at %.9f, %.9f, %.3f m (WGS84 φ, λ, h); in %s "
                  "(%s heights)\n",
                  f["origin_latitude"].get<double>(), f["origin_longitude"].get<double>(),
                  f["origin_height"].get<double>(), g["crs"].get<std::string>().c_str(),
                  g["heights"].get<std::string>().c_str())
        << "  PROJ pipeline       " << f["proj_pipeline"].get<std::string>() << "\n";
  }
  out << Format("  unit weight         σ0² %.4g (%lld degrees of freedom)\n",
                g["sigma0_squared"].get<double>(),
                static_cast<long long>(g["degrees_of_freedom"].get<int64_t>()));
  if (j.contains("camera_priors")) PrintFlagged("  priors flagged      ", j["camera_priors"], out);
  if (j.contains("control_points")) PrintFlagged("  control flagged     ", j["control_points"], out);
}

}  // namespace

// The truth's lines and the ranks' table (solve_summary_text_more.cc).
void PrintTruth(const Json& j, std::ostream& out);
void PrintRanks(const Json& j, std::ostream& out);

void PrintSolveSummary(const Json& j, std::ostream& out) {
  out << "\nSummary\n";
  PrintCosts(j, out);
  out << "  gauge held by       " << j["gauge"].get<std::string>() << "\n";
  if (j.contains("covariance") && j["covariance"].contains("error")) {
    out << "  covariance          failed: " << j["covariance"]["error"].get<std::string>() << "\n";
  } else if (j.contains("covariance")) {
    const Json& c = j["covariance"];
    out << "  covariance          " << (c["datum"] == "inner" ? "inner constraints over the centres" : "absolute")
        << ", " << c["scale"].get<std::string>() << ", sigma0 " << c["sigma0_px"].get<double>()
        << " px (redundancy " << c["redundancy"].get<int64_t>() << "), factor "
        << c["factor_nonzeros"].get<int64_t>() << " values, " << c["seconds"].get<double>() << " s\n";
  }
  if (j.value("observations_behind_cameras", int64_t{0}) > 0) {
    out << "  behind cameras      " << j["observations_behind_cameras"].get<int64_t>()
        << " observations had their point behind the camera at the start (kept; COLMAP drops "
           "them before adjusting)\n";
  }
  PrintSolver(j, out);
  PrintSizes(j, out);
  PrintRejection(j, out);
  PrintGeoreferencing(j, out);
  PrintTruth(j, out);
  PrintRanks(j, out);
}

void PrintSolveReport(const SolveReport& report, std::ostream& out) {
  PrintSolveSummary(SolveSummary(report), out);
}

}  // namespace dba
