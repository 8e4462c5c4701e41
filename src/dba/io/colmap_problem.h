// A COLMAP sparse model as a photogrammetric bundle-adjustment problem
// (Problem with CameraModel::kPhoto, camera/photo_camera.h), and the
// adjusted parameters written back into the model.
//
// Mapping (COLMAP's conventions are the photo model's, so no sign flips):
//   problem camera i   an image of the model, in image-id order (the
//                      first, the lowest id, holds the gauge); only images
//                      with at least one observation of an adjusted point
//                      (others are not in the problem and stay unchanged)
//   pose               ω = angle-axis of the normalised quaternion (qw, qx,
//                      qy, qz) (text files hold it unit only to ~5e-7), t =
//                      tvec; x_cam = R(ω) X + t
//   intrinsic group g  the camera's model (COLMAP's ids are LensModel's) and
//                      params as they are (LensModelOfColmapCamera): one
//                      group per COLMAP camera used by the problem's images
//                      (shared_intrinsics, groups in model.cameras order), or
//                      one group per problem image (group i = camera i);
//                      intrinsics_size is the largest parameter count. What
//                      the user holds fixed is applied afterwards, as Fixings
//                      (ColmapFixings).
//   problem point k    a 3D point whose track has at least min_track_length
//                      elements, in model order; its observations are its
//                      track elements in track order, each observing the 2D
//                      point (x, y) of the image it names.
//
// Rigs (COLMAP >= 3.12; docs/design.md §1.7): when a rig has a camera
// besides its reference sensor, the problem has rigs: each model frame with
// an image in the problem a frame (file order; its rig_from_world as read:
// COLMAP takes the images' poses from the frames), each group (a COLMAP
// camera) the rig's origin or a sensor refined from its sensor_from_rig; a
// sensor without a pose (HAS_POSE 0) starts at image ∘ frame⁻¹ of the
// first frame holding one of its images. The images' poses are composed.
// Other sensors (IMUs) are kept in the model and not modelled. A model
// whose rigs are all trivial (one camera each) solves as one without.
// Per-image intrinsics with rigs are refused (a sensor is its camera).
//
// Write-back (UpdateColmapModel): poses as quaternions with qw >= 0, points'
// xyz, and intrinsics; with rigs the frames' and sensors' poses, and a
// trivial frame at its image's pose. Each adjusted point's `error` becomes its mean
// reprojection error |r| in pixels (as COLMAP defines it) at the adjusted
// parameters. Names, colours, tracks, 2D points, image and point ids and the
// entries' order are kept. Camera ids are kept where possible:
//   for each COLMAP camera, the first image in model order that uses it keeps
//   it; if that image is in the problem, the camera gets that image's group's
//   intrinsics, otherwise the camera is left unchanged. Every other problem
//   image whose group differs from that owner's group (per-image intrinsics
//   of images that shared one camera, or the problem images of a camera whose
//   first user is not in the problem) gets one new camera per group: same
//   model, width and height, ids max existing id + 1, + 2, ... in group
//   order, appended to model.cameras. So every problem image's camera holds
//   exactly its group's intrinsics, and every image outside the problem keeps
//   its camera and intrinsics. With shared intrinsics and the first user of
//   each camera in the problem (the usual case) no camera is added.
//
// Thread safety: pure functions of their arguments (UpdateColmapModel writes
// only *model).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dba/problem/fixings.h"
#include "dba/io/colmap_model.h"
#include "dba/problem/problem.h"

namespace dba {

struct ColmapProblemOptions {
  // One intrinsic group per COLMAP camera used; false: one group per image.
  bool shared_intrinsics = true;
  // Points with shorter tracks are not adjusted (kept unchanged on
  // write-back). At least 1.
  int min_track_length = 2;
};

struct ColmapProblem {
  Problem problem;                 // model kPhoto
  std::vector<int64_t> image_index;   // problem camera i -> index into model.images
  std::vector<int64_t> point_index;   // problem point k -> index into model.points3D
  std::vector<int64_t> group_camera;  // intrinsic group g -> index into model.cameras
  std::vector<int64_t> frame_index;   // rigs: problem frame f -> index into model.frames
  // Rig sensors that are not cameras (IMUs): kept in the model as read,
  // not adjusted.
  int64_t sensors_not_modelled = 0;
};

// Builds the problem (see above). fixed_cameras is empty; fixed_intrinsics
// always has one mask per group.
// Throws dba::InputError naming `source` (e.g. the model's directory) for a
// camera model other than SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL and RADIAL
// used by a problem image (the message names the model and lists the
// supported ones), PINHOLE with fx != fy, or an image / 2D point reference
// the model does not hold; std::invalid_argument for min_track_length < 1.
ColmapProblem ProblemFromColmap(const ColmapModel& model, const ColmapProblemOptions& options,
                                const std::string& source);

// What is held fixed, in the problem's numbering (problem/fixings.h): the
// images with these COLMAP ids or names, and the intrinsics `fixed_intrinsics` names,
// in every group (group -1) or in the groups cut from the COLMAP camera
// whose id is `group`. An image or camera id the model does not have is
// refused (dba::InputError naming `source` and the id); an image or camera
// of the model that is not in the problem (no observation of an adjusted
// point) is simply not adjusted.
Fixings ColmapFixings(const ColmapModel& model, const ColmapProblem& problem,
                      const std::vector<uint32_t>& fixed_image_ids,
                      const std::vector<std::string>& fixed_image_names,
                      const std::vector<IntrinsicFixing>& fixed_intrinsics,
                      const std::string& source);

// Writes `adjusted` (the source problem after adjustment: same structure,
// new parameter values) back into `model`, which must be the model `source`
// came from (see above for what changes). Throws std::invalid_argument when
// `adjusted`'s structure differs from source.problem or `model` does not
// match the indices, when a new camera is needed and no id above the largest
// is left (2^32 - 1 in use). *model may be partly updated when it throws.
void UpdateColmapModel(const ColmapProblem& source, const Problem& adjusted,
                       ColmapModel* model);

// Removes from `model` what outlier rejection dropped from `source`'s
// problem: `observation_kept` has a flag per observation of source.problem
// (in its order, which is the order of each point's track) and
// `point_kept` one per problem point. A dropped observation loses its track
// element and its 2D point's link to the 3D point; a dropped point is
// removed from points3D with every link to it; a kept point's mean
// reprojection error is taken again over its kept observations (`adjusted`:
// the problem as passed to UpdateColmapModel). Points outside the problem
// (shorter tracks than min_track_length) are untouched. Call after
// UpdateColmapModel: the removal shifts points3D, so source.point_index no
// longer applies to `model` afterwards. std::invalid_argument when the
// flags do not match source.problem's counts or `model` does not match the
// indices.
void RemoveDroppedObservations(const ColmapProblem& source, const Problem& adjusted,
                               const std::vector<uint8_t>& observation_kept,
                               const std::vector<uint8_t>& point_kept, ColmapModel* model);

}  // namespace dba
