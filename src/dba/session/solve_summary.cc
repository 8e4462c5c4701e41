// The summary of a solve, computed once as one value (the JSON document
// that --report writes and Python's Summary reads); see solve_report.h.
#include <algorithm>

#include "dba/session/solve_report.h"
#include "dba/session/solve_summary_sections.h"

namespace dba {
namespace {

using Json = nlohmann::ordered_json;

Json TrafficJson(const TrafficStats& t) {
  Json j;
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

Json LossJson(const RobustLoss& loss) {
  return {{"type", LossName(loss.type)}, {"scale_px", loss.scale}};
}

// Costs are the robust ½ Σ ρ(|r|²); RMS figures are of the plain residuals,
// over all observations and over the inliers (|r| within the loss scale;
// all, for the trivial loss). Initial figures over the loaded observations,
// final ones over those left after outlier rejection.
void CostFigures(const SolveReport& r, Json& j) {
  const LmSummary& lm = r.solve.ba.lm;
  const double n0 = static_cast<double>(r.num_observations);
  const double n = static_cast<double>(lm.num_observations);
  j["initial_cost"] = lm.initial_cost;
  j["final_cost"] = lm.final_cost;
  j["loss"] = LossJson(r.loss);
  j["final_loss"] = LossJson(r.final_loss);  // the loss of final_cost
  j["initial_rms_px"] = LmSummary::Rms(lm.initial_residuals.squared, n0);
  j["final_rms_px"] = LmSummary::Rms(lm.final_residuals.squared, n);
  j["initial_inliers"] = static_cast<int64_t>(lm.initial_residuals.inliers);
  j["final_inliers"] = static_cast<int64_t>(lm.final_residuals.inliers);
  j["initial_inlier_rms_px"] =
      LmSummary::Rms(lm.initial_residuals.inlier_squared, lm.initial_residuals.inliers);
  j["final_inlier_rms_px"] =
      LmSummary::Rms(lm.final_residuals.inlier_squared, lm.final_residuals.inliers);
  j["final_observations"] = lm.num_observations;
}

void SolverFigures(const SolveReport& r, Json& j) {
  const LmSummary& lm = r.solve.ba.lm;
  j["iterations"] = lm.iterations;
  j["accepted_iterations"] = lm.accepted_iterations;
  j["pcg_iterations"] = lm.total_linear_iterations;
  const RcsSolverChoice& c = lm.linear_solver;
  j["linear_solver"] = {{"type", LinearSolverName(c.type)},
                        {"reason", c.reason},
                        {"bytes", lm.linear_solver_bytes},
                        {"pcg_double_from_iteration", lm.pcg_double_from_iteration},
                        {"pcg_path_bytes", c.pcg_bytes},
                        {"factor_budget_bytes", c.budget_bytes},
                        {"dense_factor_bytes", c.dense_bytes},
                        {"sparse_factor_bytes_estimate", c.sparse_bytes},
                        {"estimated_seconds",
                         {{"pcg", c.estimated_pcg_seconds},
                          {"dense", c.estimated_dense_seconds},
                          {"sparse", c.estimated_sparse_seconds}}}};
  const LinearSolverOptions& o = r.linear_solver;
  j["linear_solver"]["options"] = {{"type", LinearSolverName(o.type)},
                                   {"preconditioner", PreconditionerName(o.preconditioner)},
                                   {"coarse_size", o.coarse_aggregate_size},
                                   {"coarse_basis", CoarseBasisName(o.coarse_basis)},
                                   {"eta", o.pcg.eta},
                                   {"pcg_tolerance", o.pcg.relative_tolerance},
                                   {"pcg_min_iterations", o.pcg.min_iterations},
                                   {"pcg_max_iterations", o.pcg.max_iterations},
                                   {"pcg_precision", PcgPrecisionName(o.pcg.precision)}};
  j["memory_check"] = r.memory_check;
  if (!r.checkpoint_path.empty()) {
    j["checkpoints"] = {{"path", r.checkpoint_path}, {"written", r.checkpoints_written}};
  }
  j["termination"] = TerminationReasonName(lm.termination);
  j["termination_message"] = lm.termination_message;
  j["seconds"] = {{"startup", r.startup_seconds},
                  {"read", r.read_seconds},
                  {"load", r.load_seconds},
                  {"distribution", r.solve.distribution_seconds},
                  {"setup", r.solve.ba.symbolic_seconds},
                  {"rcs_formation", lm.times.rcs_formation},
                  {"linear_solve", lm.times.linear_solve},
                  {"back_substitution", lm.times.back_substitution},
                  {"analysis", r.analysis_seconds},
                  {"write", r.write_seconds},
                  {"other", r.OtherSeconds()},
                  {"total", r.total_seconds}};
}

void MemoryFigures(const SolveReport& r, Json& j) {
  const RcsFootprint& rcs = r.solve.ba.rcs;
  const double per_obs = 1.0 / static_cast<double>(std::max<int64_t>(r.num_observations, 1));
  j["memory"] = {{"peak_bytes", r.peak_memory_bytes},
                 {"peak_bytes_per_observation", r.peak_memory_bytes * per_obs},
                 {"problem_bytes", r.problem_bytes},
                 {"problem_bytes_per_observation", r.problem_bytes * per_obs},
                 {"rcs_block_rows", rcs.block_rows},
                 {"rcs_bsmc_structure_bytes", rcs.bsmc_structure_bytes},
                 {"rcs_bsmc_value_bytes", rcs.bsmc_value_bytes},
                 {"rcs_csr_bytes", rcs.csr_bytes},
                 {"rcs_blocks", rcs.blocks}};
  if (r.memory_estimate.total() <= 0) return;
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
                             {"available_bytes", r.available_memory_bytes},
                             {"description", e.Describe()}};
}

void RejectionFigures(const SolveReport& r, Json& j) {
  if (r.reject_outliers_px > 0) {
    Json rounds = Json::array();
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
}

void DistributedFigures(const SolveOnRanksSummary& s, Json& j) {
  if (s.ranks <= 1) return;
  Json d;
  d["partition"] = PartitionSchemeName(s.partition);
  d["rcs"] = RcsPlacementName(s.rcs);
  d["main_rank_forms_sub_rcs"] = s.main_forms;
  Json ranks = Json::array();
  for (const RankReport& k : s.rank_reports) {
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
    if (k.rank > 0 && k.rank < static_cast<int>(s.rank_per_iteration.size())) {
      Json per = Json::array();
      for (const TrafficStats& t : s.rank_per_iteration[k.rank]) per.push_back(TrafficJson(t));
      ranks.back()["communication_per_formation"] = per;
    }
  }
  d["ranks"] = ranks;
  d["communication"] = TrafficJson(s.traffic);
  Json per = Json::array();
  for (const TrafficStats& t : s.per_iteration) per.push_back(TrafficJson(t));
  d["communication_per_iteration"] = per;
  j["distributed"] = d;
}

Json History(const LmSummary& lm) {
  Json history = Json::array();
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
  return history;
}

}  // namespace

Json SolveSummary(const SolveReport& r) {
  const RcsFootprint& rcs = r.solve.ba.rcs;
  Json j;
  j["input"] = r.input;
  j["num_images"] = r.num_cameras;
  j["num_cameras"] = r.num_cameras;  // deprecated: images, as num_images
  j["num_intrinsic_groups"] = r.num_intrinsic_groups;
  if (r.num_colmap_cameras > 0) {
    j["num_colmap_cameras"] = r.num_colmap_cameras;
    j["num_colmap_cameras_used"] = r.num_colmap_cameras_used;
    j["num_colmap_sensors_not_modelled"] = r.num_colmap_sensors_not_modelled;
  }
  j["camera_unknowns"] = rcs.camera_unknowns;
  j["unknowns"] = rcs.camera_unknowns + 3 * r.num_points;
  Json by_kind = Json::object();
  for (int k = 0; k < kNumBlockKinds; ++k) {
    if (r.unknowns_by_kind[k] > 0) by_kind[BlockKindName(static_cast<BlockKind>(k))] = r.unknowns_by_kind[k];
  }
  j["camera_unknowns_by_kind"] = by_kind;
  j["num_points"] = r.num_points;
  j["num_observations"] = r.num_observations;
  if (r.observations_behind_cameras >= 0) j["observations_behind_cameras"] = r.observations_behind_cameras;
  j["threads"] = r.threads;
  j["ranks"] = r.solve.ranks;
  CostFigures(r, j);
  j["gauge"] = r.gauge;
  if (!r.covariance.error.empty()) j["covariance"] = {{"error", r.covariance.error}};
  if (r.covariance.computed) {
    const SolveReport::Covariance& c = r.covariance;
    j["covariance"] = {{"datum", c.datum},
                       {"scale", c.unit ? "unit" : "a-posteriori"},
                       {"variance_factor", c.variance_factor},
                       {"sigma0_px", std::sqrt(c.variance_factor)},
                       {"redundancy", c.redundancy},
                       {"factor_nonzeros", c.factor_nonzeros},
                       {"inversion_flops", c.inversion_flops},
                       {"factor_seconds", c.factor_seconds},
                       {"seconds", c.seconds}};
    Json groups = Json::array();
    for (const IntrinsicsCovariance& g : c.intrinsics) {
      const Eigen::VectorXd sigma = g.covariance.diagonal().cwiseSqrt();
      Json correlation = Json::array();
      for (Eigen::Index a = 0; a < sigma.size(); ++a) {
        Json row = Json::array();
        for (Eigen::Index b = 0; b < sigma.size(); ++b) row.push_back(g.covariance(a, b) / (sigma[a] * sigma[b]));
        correlation.push_back(row);
      }
      groups.push_back({{"group", g.group},
                        {"parameters", g.parameters},
                        {"sigma", std::vector<double>(sigma.data(), sigma.data() + sigma.size())},
                        {"correlation", correlation}});
    }
    j["covariance"]["intrinsics"] = groups;
    Json control = Json::array();
    for (const auto& p : c.control_points) {
      const Eigen::Vector3d sigma = p.covariance.diagonal().cwiseSqrt();
      control.push_back({{"name", p.name}, {"sigma", {sigma[0], sigma[1], sigma[2]}}});
    }
    if (!control.empty()) j["covariance"]["control_points"] = control;
    if (c.undetermined_points >= 0) j["covariance"]["undetermined_points"] = c.undetermined_points;
    j["covariance"]["undetermined_images"] = c.undetermined_images;
    j["covariance"]["undetermined_intrinsic_groups"] = c.undetermined_groups;
  }
  SolverFigures(r, j);
  MemoryFigures(r, j);
  RejectionFigures(r, j);
  GeoreferencingFigures(r.geo, j);
  TruthFigures(r, j);
  DistributedFigures(r.solve, j);
  j["history"] = History(r.solve.ba.lm);
  return j;
}

std::string SolveReportJson(const SolveReport& r) { return SolveSummary(r).dump(2) + "\n"; }

}  // namespace dba
