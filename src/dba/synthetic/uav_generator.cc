// Synthetic UAV surveys; see uav_generator.h.
#include "dba/synthetic/uav_generator.h"
#include "dba/camera/pose_similarity.h"
#include "dba/io/atomic_output_file.h"

#include <numbers>

#include "dba/camera/typical_lens.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "dba/io/path_kind.h"
#include "dba/camera/bal_camera.h"
#include "dba/camera/photo_camera.h"
#include "dba/common/timer.h"
#include "dba/io/bal_writer.h"
#include "dba/io/binary_problem.h"
#include "dba/camera/rig_pose.h"
#include "dba/synthetic/rig_survey.h"

namespace dba {
namespace {

// splitmix64: independent, reproducible streams from (seed, index).
uint64_t Mix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// Rolling terrain: enough relief (±25 m under a 100 m flight) that focal
// length and flying height are not interchangeable for nadir images.
double Terrain(double x, double y) { return 25.0 * std::sin(x / 60.0) * std::cos(y / 80.0); }

struct Layout {
  int64_t strips, per_strip, images;
  double footprint, along, across;  // metres
  double x0, x1, y0, y1, tile;      // ground area and tile size
  int64_t tiles_x, tiles_y;
  double points_per_tile;
};

Layout MakeLayout(const UavSurveyOptions& o) {
  if (o.field_of_view != 0 && !(o.field_of_view > 0 && o.field_of_view < 160)) {
    throw std::invalid_argument("field of view " + std::to_string(o.field_of_view) +
                                " degrees: must be in (0, 160)");
  }
  Layout l;
  l.footprint = o.image_size / o.focal_px * o.flying_height;
  l.along = l.footprint * (1.0 - o.forward_overlap);
  l.across = l.footprint * (1.0 - o.side_overlap);
  l.strips = std::max<int64_t>(1, std::llround(std::sqrt(o.images * l.along / l.across)));
  l.per_strip = (o.images + l.strips - 1) / l.strips;
  l.strips = (o.images + l.per_strip - 1) / l.per_strip;
  l.images = o.images;
  l.x0 = -l.footprint / 2;
  l.x1 = (l.per_strip - 1) * l.along + l.footprint / 2;
  l.y0 = -l.footprint / 2;
  l.y1 = (l.strips - 1) * l.across + l.footprint / 2;
  l.tile = std::min(l.along, l.across);
  l.tiles_x = static_cast<int64_t>(std::ceil((l.x1 - l.x0) / l.tile));
  l.tiles_y = static_cast<int64_t>(std::ceil((l.y1 - l.y0) / l.tile));
  // Each image sees `features_per_image` points on average.
  l.points_per_tile = o.features_per_image / (l.footprint * l.footprint) * l.tile * l.tile;
  return l;
}

// True cameras (BAL: P = R X + t, looking down -z) and the initial ones.
void MakeCameras(const UavSurveyOptions& o, const Layout& l, std::vector<double>* truth,
                 std::vector<double>* initial) {
  truth->resize(kBalCameraSize * l.images);
  initial->resize(kBalCameraSize * l.images);
  std::vector<double> focal_error(o.physical_cameras);
  {
    std::mt19937_64 rng(Mix(o.seed ^ 0xca3e7a5ULL));
    std::normal_distribution<double> n01(0.0, 1.0);
    for (double& e : focal_error) e = 1.0 + o.focal_perturbation * n01(rng);
  }
  for (int64_t i = 0; i < l.images; ++i) {
    std::mt19937_64 rng(Mix(o.seed * 0x100000001b3ULL + static_cast<uint64_t>(i)));
    std::normal_distribution<double> n01(0.0, 1.0);
    const int64_t s = i / l.per_strip, m = i % l.per_strip;
    const Vec3 centre(m * l.along + 1.0 * n01(rng), s * l.across + 1.0 * n01(rng),
                      o.flying_height + 2.0 * n01(rng));
    const Vec3 omega(0.05 * n01(rng), 0.05 * n01(rng), 0.05 * n01(rng));
    const int cam = static_cast<int>(s % o.physical_cameras);
    const double f = o.focal_px * (1.0 + 0.01 * cam), k1 = -0.05 + 0.01 * cam, k2 = 0.002;
    double* t = truth->data() + kBalCameraSize * i;
    const Vec3 tr = -AngleAxisToRotation(omega) * centre;
    const double values[9] = {omega.x(), omega.y(), omega.z(), tr.x(), tr.y(), tr.z(), f, k1, k2};
    std::copy(values, values + 9, t);
    // Initial: perturbed rotation and centre, the physical camera's focal error.
    const Vec3 omega0 = omega + o.rotation_perturbation * Vec3(n01(rng), n01(rng), n01(rng));
    const Vec3 centre0 = centre + o.position_perturbation * Vec3(n01(rng), n01(rng), n01(rng));
    const Vec3 tr0 = -AngleAxisToRotation(omega0) * centre0;
    const double init[9] = {omega0.x(), omega0.y(), omega0.z(), tr0.x(), tr0.y(), tr0.z(),
                            f * focal_error[cam], k1, k2};
    std::copy(init, init + 9, initial->data() + kBalCameraSize * i);
  }
}

// Physical camera (intrinsic group) of image i.
int PhysicalCamera(const UavSurveyOptions& o, const Layout& l, int64_t i) {
  return static_cast<int>((i / l.per_strip) % o.physical_cameras);
}

// The photogrammetric camera side of BAL cameras `bal` (true or initial):
// each pose turned into COLMAP's axes (flip the camera's y and z), one
// intrinsic group per physical camera used, with f from the group's first
// image (the same for all its images) and a principal point a few pixels off
// the centre.
Problem PhotoCameraSide(const UavSurveyOptions& o, const Layout& l,
                           const std::vector<double>& bal) {
  Problem p;
  p.model = CameraModel::kPhoto;
  const int64_t groups = std::min<int64_t>(o.physical_cameras, l.strips);
  p.camera_intrinsics.resize(l.images);
  const bool radial = o.camera_model == LensModel::kRadial;
  if (!radial) {
    p.group_models.assign(groups, o.camera_model);
    p.intrinsics_size = LensModelParams(o.camera_model);
  }
  p.cameras.resize(kPhotoPoseSize * l.images + int64_t{p.intrinsics_size} * groups);
  const Mat3 flip = Vec3(1, -1, -1).asDiagonal();
  for (int64_t i = 0; i < l.images; ++i) {
    const double* c = bal.data() + kBalCameraSize * i;
    const Eigen::AngleAxisd aa(Mat3(flip * AngleAxisToRotation(Vec3(c[0], c[1], c[2]))));
    const Vec3 omega = aa.angle() * aa.axis(), t = flip * Vec3(c[3], c[4], c[5]);
    double* pose = p.camera(i);
    for (int k = 0; k < 3; ++k) pose[k] = omega[k], pose[3 + k] = t[k];
    const int cam = PhysicalCamera(o, l, i);
    p.camera_intrinsics[i] = cam;
    if (i == cam * l.per_strip) {  // the group's first image (strip cam)
      const double half = o.image_size / 2;
      if (radial) {
        const double values[5] = {c[6], half + 1.5 + 2.0 * cam, half - 2.5 + 1.0 * cam, c[7], c[8]};
        std::copy(values, values + 5, p.intrinsics(cam));
      } else {
        // The BAL camera's focal error scales every focal length.
        std::vector<double> values = TypicalLensParams(
            o.camera_model, LensFocal(o) * c[6] / o.focal_px, o.image_size, o.image_size);
        if (const auto cx = LensModelParamIndex(o.camera_model, "cx")) {
          values[*cx] += 2.0 * cam;
          values[*cx + 1] += 1.0 * cam;
        }
        std::copy(values.begin(), values.end(), p.intrinsics(cam));
      }
    }
  }
  return p;
}

// Calls emit(true X, initial X, cameras, true pixels, noisy pixels) for every
// point with at least two observations, tile by tile. project(i, X, &pixel)
// is the true projection into image i, false when outside the image.
// With a rig, the candidates are frames and each frame's S images
// (f · S + s) are tried in turn, sensor s keeping a point it sees with
// probability rig->keep[s].
template <typename Project, typename Emit>
void ForEachPoint(const UavSurveyOptions& o, const Layout& l, Project project,
                  const std::function<void(double)>& progress, Emit emit,
                  const RigSensors* rig = nullptr) {
  const int64_t sensors = rig != nullptr ? static_cast<int64_t>(rig->keep.size()) : 1;
  std::vector<int32_t> seen;
  std::vector<double> clean, noisy;
  for (int64_t ty = 0; ty < l.tiles_y; ++ty) {
    if (progress) progress(static_cast<double>(ty) / l.tiles_y);
    for (int64_t tx = 0; tx < l.tiles_x; ++tx) {
      std::mt19937_64 rng(Mix(Mix(o.seed) + static_cast<uint64_t>(ty * l.tiles_x + tx)));
      std::uniform_real_distribution<double> u01(0.0, 1.0);
      std::normal_distribution<double> n01(0.0, 1.0);
      // Mismatches from their own stream: without them the files are as before.
      std::mt19937_64 mismatch_rng(Mix(Mix(o.seed ^ 0x6d69736dULL) + static_cast<uint64_t>(ty * l.tiles_x + tx)));
      // The image in pixel coordinates: BAL's origin is its centre, COLMAP's
      // the top-left corner.
      const double image_min = o.model == CameraModel::kBal ? -0.5 * o.image_size : 0.0;
      int64_t count = static_cast<int64_t>(l.points_per_tile);
      if (u01(rng) < l.points_per_tile - count) ++count;
      for (int64_t q = 0; q < count; ++q) {
        const double x = l.x0 + (tx + u01(rng)) * l.tile, y = l.y0 + (ty + u01(rng)) * l.tile;
        const double X[3] = {x, y, Terrain(x, y)};
        const double X0[3] = {X[0] + o.position_perturbation * n01(rng),
                              X[1] + o.position_perturbation * n01(rng),
                              X[2] + o.position_perturbation * n01(rng)};
        seen.clear();
        clean.clear();
        noisy.clear();
        // Candidate images: strips and positions whose footprint may hold X.
        const double reach = std::max(0.75 * l.footprint,
                                      rig != nullptr ? rig->reach + 0.1 * l.footprint : 0.0);
        const int64_t s0 = std::max<int64_t>(0, static_cast<int64_t>(std::floor((y - reach) / l.across)));
        const int64_t s1 = std::min<int64_t>(l.strips - 1, static_cast<int64_t>(std::ceil((y + reach) / l.across)));
        const int64_t m0 = std::max<int64_t>(0, static_cast<int64_t>(std::floor((x - reach) / l.along)));
        const int64_t m1 = std::min<int64_t>(l.per_strip - 1, static_cast<int64_t>(std::ceil((x + reach) / l.along)));
        for (int64_t s = s0; s <= s1; ++s) {
          for (int64_t m = m0; m <= m1; ++m) {
            const int64_t frame = s * l.per_strip + m;
            if (frame >= l.images) continue;
            for (int64_t q = 0; q < sensors; ++q) {
            const int64_t i = frame * sensors + q;
            Vec2 px;
            if (!project(i, X, &px)) continue;
            if (rig != nullptr && rig->keep[q] < 1.0 && u01(rng) >= rig->keep[q]) continue;
            seen.push_back(static_cast<int32_t>(i));
            clean.push_back(px.x());
            clean.push_back(px.y());
            Vec2 observed;
            observed.x() = px.x() + o.pixel_noise * n01(rng);  // x's draw first
            observed.y() = px.y() + o.pixel_noise * n01(rng);
            if (o.outlier_fraction > 0 && u01(mismatch_rng) < o.outlier_fraction) {
              do {
                observed.x() = image_min + o.image_size * u01(mismatch_rng);
                observed.y() = image_min + o.image_size * u01(mismatch_rng);
              } while ((observed - px).norm() < kOutlierMinDistance);
            }
            noisy.push_back(observed.x());
            noisy.push_back(observed.y());
            }
          }
        }
        if (seen.size() >= 2) emit(X, X0, seen, clean, noisy);
      }
    }
  }
  if (progress) progress(1.0);
}

}  // namespace

bool IsFisheyeModel(LensModel m) {
  switch (m) {
    case LensModel::kOpenCVFisheye:
    case LensModel::kSimpleRadialFisheye:
    case LensModel::kRadialFisheye:
    case LensModel::kThinPrismFisheye:
    case LensModel::kRadTanThinPrismFisheye:
    case LensModel::kSimpleFisheye:
    case LensModel::kFisheye:
      return true;
    default:
      return false;
  }
}

double LensFocal(const UavSurveyOptions& o) {
  if (o.field_of_view <= 0 || !IsFisheyeModel(o.camera_model)) return o.focal_px;
  const double half_angle = 0.5 * o.field_of_view * std::numbers::pi / 180.0;
  return 0.5 * o.image_size / half_angle;
}

// The priors file of o.priors_path from the true cameras (see the header).
void WriteGnssPriors(const UavSurveyOptions& o, const Problem& true_side) {
  std::mt19937_64 rng(Mix(o.seed ^ 0x676e7373ULL));
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::string text =
      "# dba generate: GNSS camera centres (world frame, metres): IMAGE X Y Z SIGMA_XY SIGMA_Z\n";
  char line[256];
  std::vector<uint8_t> frame_done(true_side.num_frames(), 0);
  for (int64_t i = 0; i < true_side.num_images(); ++i) {
    if (true_side.has_rigs() && std::exchange(frame_done[true_side.image_frame[i]], 1)) continue;
    Vec3 c = AntennaPosition(true_side.cameras.data() + ExposurePoseOffset(true_side, i), o.lever_arm);
    const bool outlier = u01(rng) < o.gnss_outliers;
    if (outlier) {
      const Vec3 direction = Vec3(n01(rng), n01(rng), n01(rng)).normalized();
      c += (20.0 + 30.0 * u01(rng)) * direction;
    } else {
      c += Vec3(o.gnss_sigma_xy * n01(rng), o.gnss_sigma_xy * n01(rng), o.gnss_sigma_z * n01(rng));
    }
    std::snprintf(line, sizeof line, "%lld %.6f %.6f %.6f %g %g%s\n", static_cast<long long>(i),
                  c.x(), c.y(), c.z(), o.gnss_sigma_xy, o.gnss_sigma_z,
                  outlier ? " # outlier" : "");
    text += line;
  }
  WriteFileAtomically(o.priors_path, text);
}

// The ground-control file of o.gcps_path (see the header); project(i, X,
// &pixel) is the true projection, false outside image i.
template <typename Project>
void WriteGroundControl(const UavSurveyOptions& o, const Layout& l, int64_t images,
                        Project project) {
  std::mt19937_64 rng(Mix(o.seed ^ 0x67637073ULL));
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::string text =
      "# dba generate: ground control (world frame, metres)\n"
      "# NAME X Y Z SIGMA_XY SIGMA_Z control|check, then its measurements NAME IMAGE x y\n";
  char line[256];
  for (int64_t q = 0; q < o.control_points + o.check_points; ++q) {
    const bool control = q < o.control_points;
    char name[32];
    std::snprintf(name, sizeof name, "%s%03lld", control ? "GCP" : "CHK",
                  static_cast<long long>(control ? q + 1 : q - o.control_points + 1));
    const double x = l.x0 + (0.1 + 0.8 * u01(rng)) * (l.x1 - l.x0);
    const double y = l.y0 + (0.1 + 0.8 * u01(rng)) * (l.y1 - l.y0);
    const double X[3] = {x, y, Terrain(x, y)};
    const Vec3 surveyed(X[0] + o.gcp_sigma_xy * n01(rng), X[1] + o.gcp_sigma_xy * n01(rng),
                        X[2] + o.gcp_sigma_z * n01(rng));
    std::snprintf(line, sizeof line, "%s %.6f %.6f %.6f %g %g %s # true %.6f %.6f %.6f\n", name,
                  surveyed.x(), surveyed.y(), surveyed.z(), o.gcp_sigma_xy, o.gcp_sigma_z,
                  control ? "control" : "check", X[0], X[1], X[2]);
    text += line;
    for (int64_t i = 0; i < images; ++i) {
      Vec2 px;
      if (!project(i, X, &px)) continue;
      px += o.pixel_noise * Vec2(n01(rng), n01(rng));
      std::snprintf(line, sizeof line, "%s %lld %.4f %.4f\n", name, static_cast<long long>(i),
                    px.x(), px.y());
      text += line;
    }
  }
  WriteFileAtomically(o.gcps_path, text);
}

void CheckRigSurvey(const UavSurveyOptions& o, bool cameras_given) {
  if (o.rig.empty()) return;
  if (o.model != CameraModel::kPhoto || o.unaligned) {
    throw std::invalid_argument(
        "generate: --rig needs --model photo, and is not combined with --unaligned yet");
  }
  const int64_t s = RigSensorCount(o.rig);
  if (cameras_given || o.physical_cameras != 1) {
    throw std::invalid_argument("--cameras: not with --rig (the " + o.rig + " rig's " +
                                std::to_string(s) + " sensors are its cameras)");
  }
  if (o.images % s != 0 || o.images < 2 * s) {
    const int64_t below = o.images / s * s;
    throw std::invalid_argument(
        "--images " + std::to_string(o.images) + ": every frame of a " + o.rig + " rig holds its " +
        std::to_string(s) + " sensors' images, and a survey two frames or more: give a multiple of " +
        std::to_string(s) + " from " + std::to_string(2 * s) + " (e.g. " +
        (below >= 2 * s ? std::to_string(below) + " or " : std::string()) +
        std::to_string(std::max(below + s, 2 * s)) + ")");
  }
}

namespace {

// What GenerateUavSurvey cannot honour, refused.
void CheckSurveyOptions(const UavSurveyOptions& o, const std::string& path,
                        const std::string& truth_path) {
  if (o.model != CameraModel::kPhoto && o.camera_model != LensModel::kRadial) {
    throw std::invalid_argument("generate: a camera model other than RADIAL needs the photo model");
  }
  if (o.images < 2 || o.features_per_image <= 0 || o.physical_cameras < 1 ||
      !(o.forward_overlap > 0 && o.forward_overlap < 1) ||
      !(o.side_overlap > 0 && o.side_overlap < 1) || o.pixel_noise < 0 ||
      !(o.outlier_fraction >= 0 && o.outlier_fraction < 1)) {
    throw std::invalid_argument(
        "generate: need images >= 2, features > 0, cameras >= 1, overlaps in (0, 1), noise >= 0, "
        "outliers in [0, 1)");
  }
  const bool binary = KindOfPath(path) == PathKind::kBinary;
  if (o.model == CameraModel::kPhoto &&
      (!binary || (!truth_path.empty() && KindOfPath(truth_path) != PathKind::kBinary))) {
    throw std::invalid_argument(
        "generate: the photogrammetric model needs .dba outputs (the BAL text format cannot "
        "hold intrinsics shared by several images)");
  }
  CheckRigSurvey(o);
}

// --unaligned: the initial cameras and points moved by a random similarity
// (camera/pose_similarity.h: every camera sees the same).
Similarity UnalignedSimilarity(uint64_t seed) {
  Similarity unaligned;
  std::mt19937_64 rng(Mix(seed ^ 0x616c69676eULL));
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  unaligned.scale = std::exp2(u(rng));
  const Vec3 axis = Vec3(u(rng), u(rng), u(rng)).normalized();
  unaligned.rotation = AngleAxisToRotation(3.0 * u(rng) * axis);
  unaligned.translation = 1000.0 * Vec3(u(rng), u(rng), u(rng));
  return unaligned;
}

// The written camera sides, true and initial: poses, and with the photo
// model the intrinsic groups and the rig.
void MakeCameraSides(const UavSurveyOptions& o, const Layout& l, const RigSensors* rig,
                     Problem* true_side, Problem* initial_side, UavSurveySummary* summary) {
  std::vector<double> true_cameras, initial_cameras;
  MakeCameras(o, l, &true_cameras, &initial_cameras);
  if (o.model != CameraModel::kPhoto) {
    true_side->cameras.swap(true_cameras);
    initial_side->cameras.swap(initial_cameras);
    return;
  }
  *true_side = PhotoCameraSide(o, l, true_cameras);
  *initial_side = PhotoCameraSide(o, l, initial_cameras);
  if (rig != nullptr) {
    *true_side = RigCameraSide(*true_side, rig->truth, rig->truth_first);
    *initial_side = RigCameraSide(*initial_side, rig->nominal, rig->nominal_first);
    summary->images = true_side->num_images();
    summary->frames = l.images;
  }
  summary->intrinsic_groups = true_side->num_groups();
}

// A .dba survey: pass 1 counts, pass 2 writes at the offsets the counts give.
template <typename Project, typename InitialPoint>
void WriteBinarySurvey(const UavSurveyOptions& o, const Layout& l, const Project& project,
                       const InitialPoint& initial_point, const std::function<void(double)>& progress,
                       const RigSensors* rig, const Problem& true_side, const Problem& initial_side,
                       const std::string& path, const std::string& truth_path,
                       UavSurveySummary* summary) {
  auto half_progress = [&](double base) {
    return [&progress, base](double f) { if (progress) progress(base + 0.5 * f); };
  };
  ForEachPoint(o, l, project, half_progress(0.0),
               [&](auto&, auto&, auto& seen, auto&, auto&) {
                 ++summary->points;
                 summary->observations += static_cast<int64_t>(seen.size());
               },
               rig);
  BinaryProblemWriter out(path, initial_side, summary->points, summary->observations);
  std::unique_ptr<BinaryProblemWriter> truth;
  if (!truth_path.empty()) {
    truth = std::make_unique<BinaryProblemWriter>(truth_path, true_side, summary->points,
                                                  summary->observations);
  }
  ForEachPoint(o, l, project, half_progress(0.5),
               [&](const double* X, const double* X0, const std::vector<int32_t>& seen,
                   const std::vector<double>& clean, const std::vector<double>& noisy) {
                 double x0[3];
                 initial_point(X0, x0);
                 out.AppendPoint(x0, seen, noisy);
                 if (truth) truth->AppendPoint(X, seen, clean);
               },
               rig);
  out.Commit();
  if (truth) truth->Commit();
}

// A BAL text survey: in memory (small problems, for other tools).
template <typename Project, typename InitialPoint>
void WriteBalSurvey(const UavSurveyOptions& o, const Layout& l, const Project& project,
                    const InitialPoint& initial_point, const std::function<void(double)>& progress,
                    const RigSensors* rig, const Problem& true_side, const Problem& initial_side,
                    const std::string& path, const std::string& truth_path,
                    UavSurveySummary* summary) {
  Problem problem = initial_side, truth = true_side;  // (project reads true_side)
  problem.point_offsets.push_back(0);
  truth.point_offsets.push_back(0);
  ForEachPoint(o, l, project, progress,
               [&](const double* X, const double* X0, const std::vector<int32_t>& seen,
                   const std::vector<double>& clean, const std::vector<double>& noisy) {
                 double x0[3];
                 initial_point(X0, x0);
                 problem.points.insert(problem.points.end(), x0, x0 + 3);
                 truth.points.insert(truth.points.end(), X, X + 3);
                 problem.obs_camera.insert(problem.obs_camera.end(), seen.begin(), seen.end());
                 problem.obs_pixel.insert(problem.obs_pixel.end(), noisy.begin(), noisy.end());
                 truth.obs_pixel.insert(truth.obs_pixel.end(), clean.begin(), clean.end());
                 problem.point_offsets.push_back(problem.num_observations());
               },
               rig);
  truth.obs_camera = problem.obs_camera;
  truth.point_offsets = problem.point_offsets;
  summary->points = problem.num_points();
  summary->observations = problem.num_observations();
  WriteBal(problem, path);
  if (!truth_path.empty()) WriteBal(truth, truth_path);
}

}  // namespace

UavSurveySummary GenerateUavSurvey(const UavSurveyOptions& options, const std::string& path,
                                   const std::string& truth_path,
                                   const std::function<void(double)>& progress) {
  UavSurveyOptions o = options;
  if (o.field_of_view > 0 && o.field_of_view < 160) {
    o.focal_px = 0.5 * o.image_size / std::tan(0.25 * o.field_of_view * std::numbers::pi / 90.0);
  }
  CheckSurveyOptions(o, path, truth_path);
  const bool photo = o.model == CameraModel::kPhoto;
  RigSensors rig;
  const bool rigs = !o.rig.empty();
  if (rigs) {
    rig = MakeRigSensors(o.rig, o.seed, o.flying_height, o.focal_px, o.image_size);
    const int64_t sensors = static_cast<int64_t>(rig.keep.size());
    o.images /= sensors;  // frames
    o.physical_cameras = static_cast<int>(sensors);
  }
  Timer timer;
  const Layout l = MakeLayout(o);
  UavSurveySummary summary;
  summary.images = l.images;
  summary.strips = l.strips;
  summary.images_per_strip = l.per_strip;
  Problem true_side, initial_side;
  MakeCameraSides(o, l, rigs ? &rig : nullptr, &true_side, &initial_side, &summary);
  if (!o.priors_path.empty()) WriteGnssPriors(o, true_side);
  Similarity unaligned;
  if (o.unaligned) {
    unaligned = UnalignedSimilarity(o.seed);
    for (int64_t i = 0; i < l.images; ++i) MovePose(unaligned, initial_side.camera(i));
  }
  const auto initial_point = [&](const double* X0, double* out) {
    const Vec3 x = unaligned.Apply(Vec3(X0[0], X0[1], X0[2]));
    for (int k = 0; k < 3; ++k) out[k] = x[k];
  };
  const double zero[2] = {0.0, 0.0}, half = o.image_size / 2;
  const auto project = [&](int64_t i, const double* X, Vec2* px) {
    if (photo) {
      const int32_t g = true_side.camera_intrinsics[i];
      *px = PhotoResidual(true_side.group_model(g), true_side.camera(i), true_side.intrinsics(g),
                          X, zero);
      return px->x() >= 0 && px->x() < o.image_size && px->y() >= 0 && px->y() < o.image_size;
    }
    *px = BalResidual(true_side.camera(i), X, zero);
    return std::abs(px->x()) < half && std::abs(px->y()) < half;
  };
  if (!o.gcps_path.empty()) WriteGroundControl(o, l, true_side.num_images(), project);
  if (KindOfPath(path) == PathKind::kBinary) {
    WriteBinarySurvey(o, l, project, initial_point, progress, rigs ? &rig : nullptr, true_side,
                      initial_side, path, truth_path, &summary);
  } else {
    WriteBalSurvey(o, l, project, initial_point, progress, rigs ? &rig : nullptr, true_side,
                   initial_side, path, truth_path, &summary);
  }
  summary.seconds = timer.Seconds();
  return summary;
}

}  // namespace dba
