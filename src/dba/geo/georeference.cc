// Georeferencing a solve on the main rank; see georeference.h.
#include "dba/geo/georeference.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>
#include <memory>
#include <ostream>

#include "dba/geo/georeference_input.h"
#include "dba/camera/pose_similarity.h"
#include "dba/common/error.h"
#include "dba/geo/local_frame.h"
#include "dba/io/atomic_output_file.h"
#include "dba/geo/prior_accuracy.h"
#include "dba/geo/prior_alignment.h"

namespace dba {
namespace {

std::unique_ptr<CrsToGeocentric> OpenCrs(const char* flag, const std::string& crs) {
  try {
    return std::make_unique<CrsToGeocentric>(crs);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string(flag) + ": " + e.what());
  }
}

constexpr double kMaxHeight = 1e7;  // m, ellipsoidal

std::string Figure(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

std::string Figure(const Eigen::Vector3d& v) {
  return Figure(v.x()) + ", " + Figure(v.y()) + ", " + Figure(v.z());
}

// Geocentric coordinates of `xyz` in `crs`, refused where PROJ wraps it
// or it lies beyond any height dba adjusts; a failure names the file and
// what the position belongs to.
Eigen::Vector3d Geocentric(const CrsToGeocentric& crs, const Eigen::Vector3d& xyz,
                           const std::string& path, const std::string& what) {
  Eigen::Vector3d ecef, back;
  try {
    ecef = crs.Forward(xyz);
    back = crs.Inverse(ecef);
  } catch (const std::runtime_error& e) {
    throw InputError(path, 0, what + ": " + e.what());
  }
  // A position PROJ wraps (a longitude of 400°) reads back as another one.
  if (((back - xyz).array().abs() > 1e-6 * (1.0 + xyz.array().abs())).any()) {
    throw InputError(path, 0, what + ": (" + Figure(xyz) + ") is outside the CRS's range (it reads back as (" +
                                  Figure(back) + "))");
  }
  // Nothing dba adjusts is 10,000 km off the ellipsoid (a height of 1e20 m
  // is a blunder, not an orbit).
  const double height = GeocentricToGeodetic(ecef).z();
  if (!(std::abs(height) <= kMaxHeight)) {
    throw InputError(path, 0, what + ": (" + Figure(xyz) + ") is " + Figure(height) +
                                  " m from the WGS84 ellipsoid, beyond the 1e7 m dba accepts");
  }
  return ecef;
}

// The per-axis median: one blunder among the positions moves it by no
// more than to a neighbour's value (a mean would follow the blunder).
Eigen::Vector3d Median(const std::vector<Eigen::Vector3d>& xs) {
  Eigen::Vector3d m;
  std::vector<double> axis(xs.size());
  for (int a = 0; a < 3; ++a) {
    for (size_t i = 0; i < xs.size(); ++i) axis[i] = xs[i][a];
    std::nth_element(axis.begin(), axis.begin() + axis.size() / 2, axis.end());
    m[a] = axis[axis.size() / 2];
  }
  return m;
}

// The priors and ground control from their CRSs into one local
// east-north-up frame at their median.
void ToLocalFrame(const GeoreferenceOptions& options, Georeference* geo,
                  GeoreferenceSummary* report, std::ostream& out) {
  const std::string gcp_crs = options.gcp_crs.empty() ? options.prior_crs : options.gcp_crs;
  if (!options.gcp_crs.empty() && !geo->priors.empty() && options.prior_crs.empty()) {
    throw UsageError("--gcp-crs: the camera priors are in a Cartesian frame (no --prior-crs); give "
                     "both in a CRS, or neither");
  }
  std::vector<Eigen::Vector3d> ecef;
  std::unique_ptr<CrsToGeocentric> prior_crs, control_crs;
  if (!geo->priors.empty() && !options.prior_crs.empty()) {
    prior_crs = OpenCrs("--prior-crs", options.prior_crs);
    for (const CameraCentrePrior& p : geo->priors.priors) {
      ecef.push_back(Geocentric(*prior_crs, p.centre, options.camera_priors_path,
                                "image " + geo->image_names[p.image]));
    }
  }
  if (!geo->gcps.empty() && !gcp_crs.empty()) {
    control_crs = OpenCrs(options.gcp_crs.empty() ? "--prior-crs" : "--gcp-crs", gcp_crs);
    for (const GroundControlPoint& p : geo->gcps.points) {
      ecef.push_back(Geocentric(*control_crs, p.position, options.gcps_path, "point " + p.name));
    }
  }
  if (ecef.empty()) return;
  const LocalFrame frame = LocalFrame::At(Median(ecef));
  size_t x = 0;
  if (prior_crs) {
    for (CameraCentrePrior& p : geo->priors.priors) p.centre = frame.ToLocal(ecef[x++]);
  }
  if (control_crs) {
    for (GroundControlPoint& p : geo->gcps.points) p.position = frame.ToLocal(ecef[x++]);
  }
  geo->frame = frame;
  const CrsToGeocentric& first = prior_crs ? *prior_crs : *control_crs;
  report->has_local_frame = true;
  report->local_frame_origin = frame.origin_geodetic;
  report->local_frame_pipeline = first.Pipeline();
  report->prior_crs = prior_crs ? options.prior_crs : gcp_crs;
  report->prior_heights = first.HeightKind();
  if (prior_crs && control_crs && gcp_crs != options.prior_crs) {
    report->local_frame_pipeline += "; ground control: " + control_crs->Pipeline();
    report->prior_crs += "; ground control in " + gcp_crs;
    report->prior_heights += "; ground control: " + control_crs->HeightKind();
  }
  char line[200];
  std::snprintf(line, sizeof line,
                "local frame: east, north, up at latitude %.9f, longitude %.9f, "
                "ellipsoidal height %.3f m (WGS84)\n",
                frame.origin_geodetic.x(), frame.origin_geodetic.y(), frame.origin_geodetic.z());
  out << line;
}

// `first`, then `second`: X -> s2 R2 (s1 R1 X + T1) + T2.
SimilarityFit Then(const SimilarityFit& first, const SimilarityFit& second) {
  SimilarityFit s = second;
  s.scale = second.scale * first.scale;
  s.rotation = second.rotation * first.rotation;
  s.translation = second.scale * (second.rotation * first.translation) + second.translation;
  return s;
}

// Before LM, the block onto the priors, or else onto the control points,
// by a robust similarity; what was done in one log line.
Similarity AlignBlock(const GeoreferenceOptions& options, const Georeference& geo, Problem* problem,
                      std::ostream& out) {
  const int64_t control = geo.gcps.CountControl();
  const bool on_priors = geo.priors.priors.size() >= 3 || control == 0;
  SimilarityFit fit;
  try {
    fit = on_priors ? AlignToPriors(geo.priors, *problem, Vec3::Zero())
                    : AlignToControlPoints(geo.gcps, TriangulateGroundControl(*problem, geo.gcps, true, false));
    ApplySimilarity(fit, problem, &problem->points);
    // The block in metres now: again, with the antennas where the lever arm
    // (metres) puts them.
    if (on_priors && !geo.priors.lever_arm.isZero(0.0)) {
      const SimilarityFit again = AlignToPriors(geo.priors, *problem, geo.priors.lever_arm);
      ApplySimilarity(again, problem, &problem->points);
      fit = Then(fit, again);
    }
  } catch (const std::invalid_argument& e) {
    throw InputError(on_priors ? options.camera_priors_path : options.gcps_path, 0, e.what());
  }
  char line[300];
  if (!geo.priors.empty()) {
    std::snprintf(line, sizeof line, "camera priors: %zu%s", geo.priors.priors.size(),
                  on_priors ? "; aligned onto them" : "");
    out << line;
  }
  if (!geo.gcps.empty()) {
    std::snprintf(line, sizeof line, "%scontrol points: %lld, check points: %lld%s",
                  geo.priors.empty() ? "" : "; ", static_cast<long long>(control),
                  static_cast<long long>(geo.gcps.points.size() - control),
                  on_priors ? "" : "; aligned onto the control points");
    out << line;
  }
  std::snprintf(line, sizeof line, " (scale %.6g, %lld inliers)%s\n", fit.scale,
                static_cast<long long>(fit.inliers),
                fit.collinear ? "; the positions are collinear: the roll about their line "
                                "is left to the priors inside LM"
                              : "");
  out << line;
  return fit;
}

// With rigs a prior is its image's frame's (the rig's antenna at that
// exposure): two on one frame are one position given twice.
void RefuseTwoPriorsOnAFrame(const std::string& path, const Georeference& geo,
                             const CameraSide& side) {
  std::vector<int32_t> first(side.num_frames(), -1);
  for (const CameraCentrePrior& p : geo.priors.priors) {
    int32_t& seen = first[side.image_frame[p.image]];
    if (seen >= 0) {
      throw InputError(path, 0,
                       "images " + geo.image_names[seen] + " and " + geo.image_names[p.image] +
                           " are one frame (one exposure of a rig), whose antenna has one "
                           "position: give one prior per frame");
    }
    seen = p.image;
  }
}

// Whether every prior is on a held exposure: its image held, or with rigs
// its frame (held when one of its images is, as rcs/unknown_layout holds it).
bool EveryPriorHeld(const CameraPriors& priors, const CameraSide& side) {
  std::vector<uint8_t> held_frame(side.has_rigs() ? side.num_frames() : 0, 0);
  for (int64_t i = 0; side.has_rigs() && i < side.num_images(); ++i) {
    if (side.camera_fixed(i)) held_frame[side.image_frame[i]] = 1;
  }
  return std::all_of(priors.priors.begin(), priors.priors.end(), [&](const CameraCentrePrior& p) {
    return side.has_rigs() ? held_frame[side.image_frame[p.image]] != 0 : side.camera_fixed(p.image);
  });
}

}  // namespace

Georeference PrepareGeoreference(const GeoreferenceOptions& options, const ImageNames& names,
                                 Problem* problem, GeoreferenceSummary* report, std::ostream& out,
                                 bool align) {
  Georeference geo;
  const int64_t num_images = problem->num_images();
  geo.image_names = names.problem;
  if (geo.image_names.empty()) {
    for (int64_t i = 0; i < num_images; ++i) geo.image_names.push_back(std::to_string(i));
  }
  if (!options.camera_priors_path.empty()) {
    geo.priors = LoadCameraPriors(options.camera_priors_path, names, num_images,
                                  options.prior_sigma, options.prior_loss);
    geo.priors.lever_arm = options.lever_arm;
    geo.priors.refine_lever_arm = options.refine_lever_arm;
    // A lever arm shows as the antennas' offset from cameras that can move;
    // held ones keep the offset the alignment gave them (it stayed at its
    // start: 0.002, 0.000, -0.003 m for a true 0.25, -0.15, -0.4).
    if (options.refine_lever_arm && EveryPriorHeld(geo.priors, *problem)) {
      throw UsageError(
          "--refine-lever-arm: every image with a camera prior is held (--fix-images), so nothing "
          "in the solve places the lever arm (the alignment onto the priors gives the held cameras "
          "the antennas' offset, which they keep); give it with --lever-arm X,Y,Z, or hold fewer "
          "images");
    }
    if (problem->has_rigs()) RefuseTwoPriorsOnAFrame(options.camera_priors_path, geo, *problem);
  }
  if (!options.gcps_path.empty()) {
    geo.gcps = LoadGroundControl(options.gcps_path, names, num_images);
    if (geo.priors.empty() && geo.gcps.CountControl() == 0) {
      throw InputError(options.gcps_path, 0,
                       "no control points and no --camera-priors: nothing places the block "
                       "(check points only measure it)");
    }
  }
  ToLocalFrame(options, &geo, report, out);
  if (!options.output_crs.empty()) {
    if (!geo.frame) {
      throw UsageError("--output-crs: the solve is in a Cartesian frame of its own; give the "
                       "priors' or control points' CRS (--prior-crs, --gcp-crs)");
    }
    OpenCrs("--output-crs", options.output_crs);  // refused now, not after the solve
  }

  if (align) geo.alignment = AlignBlock(options, geo, problem, out);
  AddControlPoints(geo.gcps, problem);
  geo.control_points = geo.gcps.CountControl();
  return geo;
}

std::vector<double> InOutputCrs(const GeoreferenceOptions& options, const Georeference& geo,
                                const std::vector<double>& xyz) {
  if (options.output_crs.empty() || !geo.frame) return xyz;
  const auto crs = OpenCrs("--output-crs", options.output_crs);
  std::vector<double> out(xyz.size());
  for (size_t k = 0; k + 2 < xyz.size(); k += 3) {
    const Eigen::Vector3d p = crs->Inverse(geo.frame->ToGeocentric(Eigen::Vector3d(&xyz[k])));
    for (int a = 0; a < 3; ++a) out[k + a] = p[a];
  }
  return out;
}

void WriteCameraCentres(const GeoreferenceOptions& options, const Georeference& geo,
                        const CameraSide& side, const std::vector<std::string>& image_names) {
  std::vector<double> centres;
  for (int64_t i = 0; i < side.num_images(); ++i) {
    const Vec3 c = CameraCentre(side.camera(i));
    centres.insert(centres.end(), c.data(), c.data() + 3);
  }
  centres = InOutputCrs(options, geo, centres);
  const bool crs = !options.output_crs.empty() && geo.frame;
  std::string text = "# dba solve: camera centres C = -R^T t, IMAGE X Y Z, in " +
                     (crs ? options.output_crs
                          : std::string(geo.frame ? "the local east-north-up frame of the report"
                                                  : "the solve's frame")) + "\n";
  char line[320];
  for (int64_t i = 0; i < side.num_images(); ++i) {
    const std::string name = i < static_cast<int64_t>(image_names.size()) ? image_names[i]
                                                                          : std::to_string(i);
    std::snprintf(line, sizeof line, crs ? "%s %.10f %.10f %.6f\n" : "%s %.6f %.6f %.6f\n",
                  name.c_str(), centres[3 * i], centres[3 * i + 1], centres[3 * i + 2]);
    text += line;
  }
  WriteFileAtomically(options.camera_centres_path, text);
}

void MeasureGeoreference(const Georeference& geo, const SolveFigures& solve, Problem* problem,
                         GeoreferenceSummary* report) {
  const std::vector<double> control = RemoveControlPoints(geo.control_points, problem);
  AccuracyReport& a = report->accuracy;
  a.gnss.errors = CameraPriorErrors(geo.priors, *problem, geo.image_names);
  const std::vector<Triangulation> checks = TriangulateGroundControl(*problem, geo.gcps, false, true);
  size_t c = 0, k = 0;
  for (const GroundControlPoint& p : geo.gcps.points) {
    PositionError e;
    e.name = p.name;
    e.sigma = p.sigma;
    if (p.control) {
      e.d = Eigen::Map<const Vec3>(control.data() + 3 * c++) - p.position;
      a.control.errors.push_back(e);
    } else if (const Triangulation& t = checks[k++]; t.ok) {
      e.d = t.X - p.position;
      a.check.errors.push_back(e);
    } else {
      report->check_points_not_triangulated.push_back(p.name);
    }
  }
  a.Measure();
  a.degrees_of_freedom = 2 * solve.num_observations +
                         3 * (a.gnss.figures.count + geo.control_points) -
                         (solve.camera_unknowns + 3 * (solve.num_points + geo.control_points));
  if (a.degrees_of_freedom > 0) {
    a.sigma0_squared = 2.0 * solve.final_cost / static_cast<double>(a.degrees_of_freedom);
  }
  report->has_priors = !geo.priors.empty();
  report->has_ground_control = !geo.gcps.empty();
  report->prior_loss = geo.priors.loss;
  report->lever_arm = geo.priors.lever_arm;
  report->lever_arm_refined = geo.priors.refine_lever_arm;
}

}  // namespace dba
