// Georeferencing a solve (docs/georeferencing.md), on the main rank:
// before it, GNSS camera priors and ground control read, brought into the
// solve's frame (a local east-north-up frame through PROJ when they come in
// a CRS), the block moved onto them by a robust similarity, the control
// points appended to the problem; after it, the control points taken out
// again, the check points triangulated, and the accuracy figures measured.
//
// Thread safety: one caller.
#pragma once

#include <Eigen/Core>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "dba/geo/ground_control.h"
#include "dba/geo/local_frame.h"
#include "dba/geo/prior_accuracy.h"
#include "dba/io/image_names.h"
#include "dba/problem/problem.h"
#include "dba/rcs/camera_centre_prior.h"

namespace dba {

struct GeoreferenceOptions {
  // --camera-priors (io/camera_priors_file.h): GNSS camera centres, their
  // default σ (xy, z; rows may give their own) and their loss, in σ units.
  std::string camera_priors_path;
  std::optional<Eigen::Vector2d> prior_sigma;
  std::string prior_crs;  // empty: a metric Cartesian frame
  RobustLoss prior_loss{LossType::kCauchy, 3.0};
  // --lever-arm, --refine-lever-arm: where the GNSS antenna is in the
  // camera's frame (with rigs, the rig's), metres, and whether the solve
  // estimates it (rcs/camera_centre_prior.h).
  Eigen::Vector3d lever_arm = Eigen::Vector3d::Zero();
  bool refine_lever_arm = false;
  // --gcps (io/ground_control_file.h): control and check points.
  std::string gcps_path;
  std::string gcp_crs;  // empty: prior_crs
  std::string accuracy_report_path;  // empty: none
  // --output-crs: the point cloud and the camera centres converted from the
  // local frame back into this CRS (needs --prior-crs or --gcp-crs).
  std::string output_crs;
  std::string camera_centres_path;  // --camera-centres: IMAGE X Y Z per image
  bool any() const { return !camera_priors_path.empty() || !gcps_path.empty(); }
};

struct Georeference {
  CameraPriors priors;
  GroundControl gcps;
  std::vector<std::string> image_names;  // how images are named in the report
  int64_t control_points = 0;  // appended to the problem: its last points
  std::optional<LocalFrame> frame;  // the local ENU frame, when a CRS was given
  // The similarity that moved the block onto the priors or control points
  // (none when not aligned: a resumed solve's parameters are aligned
  // already), for points the caller did not hand over (ranks reading a .dba).
  std::optional<Similarity> alignment;
  bool empty() const { return priors.empty() && gcps.empty(); }
};

// What a solve's summary says of its georeferencing.
struct GeoreferenceSummary {
  bool has_priors = false;
  bool has_ground_control = false;
  AccuracyReport accuracy;
  RobustLoss prior_loss;
  Eigen::Vector3d lever_arm = Eigen::Vector3d::Zero();  // as solved, when refined
  bool lever_arm_refined = false;
  std::vector<std::string> check_points_not_triangulated;
  // --prior-crs: the local east-north-up frame the solve ran in.
  bool has_local_frame = false;
  Eigen::Vector3d local_frame_origin = Eigen::Vector3d::Zero();  // φ, λ (deg), h (m)
  std::string local_frame_pipeline, prior_crs, prior_heights;
};

// Reads what `options` names against the problem's images (`names`: a
// COLMAP input's), converts it into the solve's frame, aligns `problem`
// onto the priors (or, without enough of them, the control points; not
// with `align` false: a resumed solve's parameters are aligned already),
// then appends the control points. Throws InputError (file, line) for bad input
// and UsageError for a CRS PROJ cannot use.
Georeference PrepareGeoreference(const GeoreferenceOptions& options, const ImageNames& names,
                                 Problem* problem, GeoreferenceSummary* summary, std::ostream& out,
                                 bool align = true);

// `xyz` (3 per point, the solve's frame) in --output-crs, or as they are
// without it. Throws std::runtime_error where PROJ cannot convert.
std::vector<double> InOutputCrs(const GeoreferenceOptions& options, const Georeference& geo,
                                const std::vector<double>& xyz);

// --camera-centres: "IMAGE X Y Z" per image (C = -Rᵀt), in --output-crs or
// the solve's frame, written atomically.
void WriteCameraCentres(const GeoreferenceOptions& options, const Georeference& geo,
                        const CameraSide& side, const std::vector<std::string>& image_names);

// What the solve measured: its final cost and observations, its
// camera-side unknowns and the problem's points (without control points).
struct SolveFigures {
  double final_cost = 0.0;
  int64_t num_observations = 0;
  int64_t camera_unknowns = 0;
  int64_t num_points = 0;
};

// After the solve, with the adjusted cameras and points (the control points
// still last): takes the control points out of `problem`, triangulates the
// check points, and fills summary->accuracy (σ0² from the solve's final
// cost).
void MeasureGeoreference(const Georeference& geo, const SolveFigures& solve, Problem* problem,
                         GeoreferenceSummary* summary);

}  // namespace dba
