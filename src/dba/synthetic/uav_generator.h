// Synthetic UAV surveys with a known ground truth like the paper's
// synthetic datasets: nadir images taken along parallel flight strips over
// gently rolling terrain, each ground point observed by every image whose
// footprint holds it, so track lengths follow from the forward and side
// overlap and every image overlaps a bounded set of neighbours.
//
// Geometry (BAL camera model, camera looking down -z): flying height H above
// the mean ground, focal f pixels, square images of `image_size` pixels, so a
// footprint is image_size / f · H metres wide. Strip s is flown with physical
// camera s mod C (of `physical_cameras` C), whose focal length, k1 and k2
// its images share.
//
// Camera models (`model`):
//   kBal    one 9-parameter BAL camera per image: the images of a physical
//           camera get the same intrinsic values, but as separate unknowns.
//   kPhoto  per image a pose (COLMAP's axes: the BAL pose turned about its
//           x axis, camera/photo_camera.h), and one intrinsic group per
//           physical camera used (min(C, strips)), shared by its images, in
//           `camera_model`: RADIAL (f, cx, cy, k1, k2, the BAL camera's f,
//           k1, k2) by default, any other lens model with
//           TypicalLensParams; the principal point is a few pixels off the
//           image centre. Only a .dba output can hold it.
// Field of view (`field_of_view`, degrees, across the image; 0: from
// focal_px): sets focal_px to the pinhole focal length of that angle, which
// sizes the footprints, and a fisheye model's f to the equidistant one
// (image_size / 2 = f · angle / 2), so wide-angle lenses fill the image.
// Both draw the same survey from the same random streams (centres,
// rotations, points, pixel noise), and perturb the initial values the same
// way: rotation and centre per image, points, and the focal length once per
// physical camera (the BAL cameras of one physical camera share the error;
// the photo model perturbs the group's f). Other intrinsics start true. Images along a strip are
// (1 - forward_overlap) footprints apart, strips (1 - side_overlap) apart.
// Ground points are drawn per terrain tile from a generator seeded by
// (seed, tile), so the output does not depend on anything but the options.
//
// Streaming: the problem is written in two passes over the tiles (count, then
// write at the computed offsets), so memory stays proportional to the images
// plus one strip of tiles, never to the observations.
//
// Thread safety: GenerateUavSurvey is independent per call.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <string>

#include "dba/problem/problem.h"

namespace dba {

struct UavSurveyOptions {
  int64_t images = 1000;
  double features_per_image = 300;  // mean observations per image
  double forward_overlap = 0.8;
  double side_overlap = 0.6;
  int physical_cameras = 1;          // images share f, k1, k2 of their camera
  double pixel_noise = 1.0;          // σ of the observation noise (pixels)
  // Fraction of observations replaced by a mismatch: a uniform random pixel
  // of the image at least kOutlierMinDistance from the true projection. The
  // ground truth keeps the true (noise-free) pixel, so an outlier is an
  // observation far from its truth (IsTrueOutlier).
  double outlier_fraction = 0.0;
  double rotation_perturbation = 1e-3;     // σ of the initial angle-axis, rad
  double position_perturbation = 0.5;      // σ of the initial camera and point positions, m
  double focal_perturbation = 0.002;       // relative σ of the initial focal length
  uint64_t seed = 1;
  double flying_height = 100.0;  // metres above mean ground
  double focal_px = 1000.0;
  double image_size = 1000.0;    // pixels, square images
  CameraModel model = CameraModel::kBal;
  LensModel camera_model = LensModel::kRadial;  // kPhoto's groups
  double field_of_view = 0.0;  // degrees, (0, 160); 0: focal_px as given
  // GNSS camera-centre priors (io/camera_priors_file.h), written when
  // priors_path is set: the true centres (world frame, metres) with
  // Gaussian noise σ_xy per horizontal axis and σ_z, and a fraction
  // gnss_outliers of the images given a gross error of 20 to 50 m in a
  // random direction instead (their lines end in "# outlier").
  std::string priors_path;
  double gnss_sigma_xy = 2.0, gnss_sigma_z = 4.0;
  double gnss_outliers = 0.0;
  // Ground control (io/ground_control_file.h), written when gcps_path is
  // set: control_points + check_points ground points spread uniformly over
  // the inner 80% of the block, surveyed with Gaussian noise σ_xy, σ_z
  // (each line ends in "# true X Y Z", the noise-free position), measured in
  // every image that sees them with the observations' pixel noise, in the
  // model's pixel convention.
  std::string gcps_path;
  int64_t control_points = 0, check_points = 0;
  double gcp_sigma_xy = 0.02, gcp_sigma_z = 0.02;
  // The GNSS antenna in the camera's (with a rig, the rig's) frame: the
  // priors are at C + Rᵀ lever_arm (rcs/camera_centre_prior.h), one per
  // frame with a rig.
  Eigen::Vector3d lever_arm = Eigen::Vector3d::Zero();
  // The initial cameras and points in a random similarity frame (scale
  // 0.5 to 2, any rotation, a shift of up to 1 km), as a reconstruction is
  // before georeferencing; the truth stays in the world frame.
  bool unaligned = false;
  // Rigs (synthetic/rig_survey.h): "" (every image its own exposure), or
  // oblique5, stereo, ring6: `images` / sensors frames along the strips,
  // each an exposure of every sensor (kPhoto, .dba version 4; each sensor
  // its own physical camera, `physical_cameras` left at 1; CheckRigSurvey).
  std::string rig;
};

// The focal length of `o`'s lens model: focal_px, or with a field of view
// the equidistant one for fisheye models (see above).
double LensFocal(const UavSurveyOptions& o);
// Whether the model is one of COLMAP's equidistant fisheye models.
bool IsFisheyeModel(LensModel m);

inline constexpr double kOutlierMinDistance = 50.0;  // pixels
// Whether an observation at `observed` whose noise-free pixel is `truth` is
// one of the generator's mismatches: over half kOutlierMinDistance away
// (25 px: 25 σ for the default noise; Gaussian noise reaches it with
// probability below 1e-5 for σ up to 5 px).
inline bool IsTrueOutlier(const double* observed, const double* truth) {
  const double dx = observed[0] - truth[0], dy = observed[1] - truth[1];
  return dx * dx + dy * dy > 0.25 * kOutlierMinDistance * kOutlierMinDistance;
}

struct UavSurveySummary {
  int64_t images = 0;
  int64_t points = 0;
  int64_t observations = 0;
  int64_t strips = 0;
  int64_t images_per_strip = 0;
  int64_t intrinsic_groups = 0;  // kPhoto: physical cameras used; kBal: 0
  int64_t frames = 0;            // with a rig: its exposures (else 0)
  double seconds = 0.0;
};

// A rig survey's options that cannot be honoured, refused by name
// (std::invalid_argument): a rig but the photo model, or --unaligned;
// `images` not a multiple of the rig's sensors or under two frames;
// --cameras given (`cameras_given`) or `physical_cameras` other than 1 (each
// sensor is a camera). Nothing without a rig.
void CheckRigSurvey(const UavSurveyOptions& o, bool cameras_given = false);

// Writes the noisy, perturbed problem to `path` (dba binary if it ends in
// .dba, else BAL text; BAL text holds it in memory, so use it for small
// sizes) and, if `truth_path` is not empty, the ground truth (true
// parameters, noise-free observations) in the same format. Both are written
// to temporary names and renamed when complete. `progress` (optional) is
// told the fraction done. Throws std::invalid_argument for bad options,
// including kPhoto with an output that is not .dba and CheckRigSurvey's.
UavSurveySummary GenerateUavSurvey(const UavSurveyOptions& options, const std::string& path,
                                   const std::string& truth_path,
                                   const std::function<void(double)>& progress = {});

}  // namespace dba
