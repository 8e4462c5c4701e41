// Sections of a solve's summary; see solve_summary_sections.h.
#include "dba/session/solve_summary_sections.h"

namespace dba {
namespace {

using Json = nlohmann::ordered_json;

Json FiguresJson(const AccuracyFigures& f) {
  return Json{{"count", f.count}, {"mean", f.mean},     {"sd", f.sd},     {"rms", f.rms},
              {"rms_3d", f.rms_3d}, {"ce90", f.ce90}, {"le90", f.le90}, {"flagged", f.flagged}};
}

Json IntrinsicsErrors(const GroundTruthErrors& t) {
  Json groups = Json::array();
  for (size_t g = 0; g < t.intrinsics_error.size(); ++g) {
    const auto& e = t.intrinsics_error[g];
    const LensModel m = t.intrinsics_model[g];
    Json group = {{"group", g}, {"model", Info(m).name}, {"f_relative", e[0] / t.true_focal[g]}};
    for (size_t p = 0; p < e.size(); ++p) group[LensModelParamName(m, static_cast<int>(p))] = e[p];
    groups.push_back(std::move(group));
  }
  return groups;
}

}  // namespace

void GeoreferencingFigures(const GeoreferenceSummary& g, Json& j) {
  const AccuracyReport& a = g.accuracy;
  if (!g.has_priors && !g.has_ground_control) return;
  j["georeferencing"] = {{"sigma0_squared", a.sigma0_squared},
                         {"degrees_of_freedom", a.degrees_of_freedom},
                         {"crs", g.prior_crs},
                         {"heights", g.prior_heights},
                         {"local_frame",
                          {{"origin_latitude", g.local_frame_origin.x()},
                           {"origin_longitude", g.local_frame_origin.y()},
                           {"origin_height", g.local_frame_origin.z()},
                           {"proj_pipeline", g.local_frame_pipeline}}}};
  j["georeferencing"]["has_local_frame"] = g.has_local_frame;
  if (g.has_priors) {
    Json p = FiguresJson(a.gnss.figures);
    p["sigma0_squared"] = a.sigma0_squared;
    p["degrees_of_freedom"] = a.degrees_of_freedom;
    p["crs"] = g.prior_crs;
    p["heights"] = g.prior_heights;
    p["local_frame"] = j["georeferencing"]["local_frame"];
    p["loss"] = {{"type", LossName(g.prior_loss.type)}, {"scale", g.prior_loss.scale}};
    p["lever_arm"] = {g.lever_arm.x(), g.lever_arm.y(), g.lever_arm.z()};
    p["lever_arm_refined"] = g.lever_arm_refined;
    j["camera_priors"] = p;
  }
  if (g.has_ground_control) {
    j["control_points"] = FiguresJson(a.control.figures);
    j["check_points"] = FiguresJson(a.check.figures);
    j["check_points"]["not_triangulated"] = g.check_points_not_triangulated;
  }
}

void TruthFigures(const SolveReport& r, Json& j) {
  if (!r.has_truth) return;
  const GroundTruthErrors& t = r.truth;
  j["ground_truth"] = {{"rms_to_noise_free_px", t.rms_to_noise_free_px},
                       {"rms_observations", t.rms_observations},
                       {"mismatches_left_out", t.mismatches_left_out},
                       {"similarity_scale", t.similarity_scale},
                       {"absolute", t.absolute},
                       {"camera_centre_rms", t.camera_centre_rms},
                       {"point_rms", t.point_rms}};
  if (!t.intrinsics_error.empty()) j["ground_truth"]["intrinsics_error"] = IntrinsicsErrors(t);
  if (!t.sensor_group.empty()) {
    j["ground_truth"]["sensors"] = {{"group", t.sensor_group},
                                    {"rotation_error_deg", t.sensor_rotation_error_deg},
                                    {"position_error", t.sensor_position_error}};
  }
  // Per camera, for a top view of the errors (python3 -m dba.plot).
  j["ground_truth"]["cameras"] = {{"true_x", t.centre_x},
                                  {"true_y", t.centre_y},
                                  {"centre_error", t.centre_error}};
}

}  // namespace dba
