// The printed summary's ground truth and ranks, rendered from the summary
// value (solve_summary_text.cc renders the rest).
#include <algorithm>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "dba/common/memory.h"
#include "dba/session/solve_report.h"

namespace dba {
namespace {

using Json = nlohmann::ordered_json;

// A group's errors: (name, value) in its model's order.
std::vector<std::pair<std::string, double>> GroupErrors(const Json& group) {
  std::vector<std::pair<std::string, double>> e;
  for (auto it = group.begin(); it != group.end(); ++it) {
    if (it.key() != "group" && it.key() != "model" && it.key() != "f_relative") {
      e.emplace_back(it.key(), it.value().get<double>());
    }
  }
  return e;
}

void PrintIntrinsicsLine(const std::string& what, const std::vector<std::pair<std::string, double>>& e,
                         double focal_relative, std::ostream& out) {
  std::string s = "  intrinsics " + what + " error";
  char buf[96];
  for (size_t j = 0; j < e.size(); ++j) {
    std::snprintf(buf, sizeof buf, "%s %s %.4g", j == 0 ? "" : ",", e[j].first.c_str(), e[j].second);
    s += buf;
    if (j == 0) {
      std::snprintf(buf, sizeof buf, " (%.3g %%)", 100.0 * focal_relative);
      s += buf;
    }
  }
  out << s << "\n";
}

// Each group's errors, or with more than 8 the largest of each parameter
// (named after the first group's model).
void PrintIntrinsicsErrors(const Json& groups, std::ostream& out) {
  if (groups.size() <= 8) {
    for (const Json& g : groups) {
      char what[16];
      std::snprintf(what, sizeof what, "%-8zu", g["group"].get<size_t>());
      PrintIntrinsicsLine(what, GroupErrors(g), g["f_relative"].get<double>(), out);
    }
    return;
  }
  std::vector<std::pair<std::string, double>> worst = GroupErrors(groups[0]);
  double worst_f = 0.0;
  for (const Json& g : groups) {
    const auto e = GroupErrors(g);
    for (size_t j = 0; j < std::min(worst.size(), e.size()); ++j) {
      worst[j].second = std::max(worst[j].second, e[j].second);
    }
    worst_f = std::max(worst_f, g["f_relative"].get<double>());
  }
  char what[64];
  std::snprintf(what, sizeof what, "(%zu groups) largest", groups.size());
  PrintIntrinsicsLine(what, worst, worst_f, out);
}

void PrintRank(const Json& k, bool spread, std::ostream& out) {
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "    rank %-3d  %10ld points %11ld observations %7ld cameras  "
                "sub-RCS %8ld blocks %10s  peak %s (estimated %s)\n",
                k["rank"].get<int>(), k["points"].get<long>(), k["observations"].get<long>(),
                k["cameras"].get<long>(), k["sub_rcs_blocks"].get<long>(),
                BytesText(k["sub_rcs_bytes"].get<double>()).c_str(),
                BytesText(k["peak_memory_bytes"].get<double>()).c_str(),
                BytesText(k["memory_estimate_bytes"].get<double>()).c_str());
  out << buf;
  if (!spread) return;
  const Json& c = k["communication"];
  const auto bytes = [&](const char* t) { return BytesText(c[t]["bytes"].get<double>()); };
  const auto seconds = [&](const char* t) { return c[t]["seconds"].get<double>(); };
  std::snprintf(buf, sizeof buf,
                "              owns %ld RCS rows, %ld blocks, %s with its solve (halo %ld "
                "rows); reduce-scatter %s %.3f s, halo %s %.3f s, reductions %s %.3f s\n",
                k["owned_rows"].get<long>(), k["owned_blocks"].get<long>(),
                BytesText(k["owned_bytes"].get<double>()).c_str(), k["halo_rows"].get<long>(),
                bytes("sub_rcs").c_str(), seconds("sub_rcs"), bytes("halo").c_str(),
                seconds("halo"), bytes("reduction").c_str(), seconds("reduction"));
  out << buf;
}

void PrintCommunication(const Json& d, double total_seconds, std::ostream& out) {
  const Json& t = d["communication"];
  const double iters = std::max<double>(static_cast<double>(d["communication_per_iteration"].size()), 1);
  out << "  communication (main rank, sent + received; waits for other ranks apart)\n";
  char buf[300];
  for (const char* c : {"distribution", "sub_rcs", "camera_update", "control", "result", "halo",
                        "reduction"}) {
    const double bytes = t[c]["bytes"], seconds = t[c]["seconds"];
    std::snprintf(buf, sizeof buf,
                  "    %-14s %12s %9.3f s  (waits %8.3f s)  per iteration %10s %8.4f s\n", c,
                  BytesText(bytes).c_str(), seconds, t[c]["wait_seconds"].get<double>(),
                  BytesText(bytes / iters).c_str(), seconds / iters);
    out << buf;
  }
  std::snprintf(buf, sizeof buf,
                "    %-14s %12s %9.3f s  (waits %8.3f s)  transfers are %.1f%% of the solve\n",
                "total", BytesText(t["total"]["bytes"].get<double>()).c_str(),
                t["total"]["seconds"].get<double>(), t["total"]["wait_seconds"].get<double>(),
                100.0 * t["total"]["seconds"].get<double>() / std::max(total_seconds, 1e-9));
  out << buf;
}

}  // namespace

void PrintTruth(const Json& j, std::ostream& out) {
  if (!j.contains("ground_truth")) return;
  const Json& t = j["ground_truth"];
  char buf[400];
  if (t["absolute"].get<bool>()) {
    std::snprintf(buf, sizeof buf,
                  "  ground truth        RMS to noise-free observations %.4f px; absolute (no\n"
                  "                      alignment): camera centres %.4g, points %.4g (RMS)\n",
                  t["rms_to_noise_free_px"].get<double>(), t["camera_centre_rms"].get<double>(),
                  t["point_rms"].get<double>());
  } else {
    std::snprintf(buf, sizeof buf,
                  "  ground truth        RMS to noise-free observations %.4f px; after a\n"
                  "                      similarity (scale %.6f): camera centres %.4g, points %.4g (RMS)\n",
                  t["rms_to_noise_free_px"].get<double>(), t["similarity_scale"].get<double>(),
                  t["camera_centre_rms"].get<double>(), t["point_rms"].get<double>());
  }
  out << buf;
  if (t["mismatches_left_out"].get<int64_t>() > 0) {
    std::snprintf(buf, sizeof buf,
                  "                      (the RMS over %lld true inliers; %lld generated "
                  "mismatches left out)\n",
                  static_cast<long long>(t["rms_observations"].get<int64_t>()),
                  static_cast<long long>(t["mismatches_left_out"].get<int64_t>()));
    out << buf;
  }
  if (t.contains("intrinsics_error")) PrintIntrinsicsErrors(t["intrinsics_error"], out);
  if (t.contains("sensors")) {
    const Json& s = t["sensors"];
    for (size_t x = 0; x < s["group"].size(); ++x) {
      std::snprintf(buf, sizeof buf, "                      sensor of group %lld: %.5f deg, %.5g in its rig\n",
                    static_cast<long long>(s["group"][x].get<int64_t>()),
                    s["rotation_error_deg"][x].get<double>(), s["position_error"][x].get<double>());
      out << buf;
    }
  }
}

void PrintRanks(const Json& j, std::ostream& out) {
  if (!j.contains("distributed")) return;
  const Json& d = j["distributed"];
  const bool spread = d["rcs"] == "distributed";
  out << "  ranks               " << j["ranks"].get<int>() << " ("
      << d["partition"].get<std::string>() << " partition, main rank "
      << (d["main_rank_forms_sub_rcs"].get<bool>() ? "forms a sub-RCS" : "coordinates only")
      << ", RCS " << (spread ? "spread over the ranks" : "gathered on rank 0") << ")\n";
  for (const Json& k : d["ranks"]) PrintRank(k, spread, out);
  PrintCommunication(d, j["seconds"]["total"].get<double>(), out);
}

}  // namespace dba
