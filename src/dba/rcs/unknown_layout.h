// The unknowns of the reduced camera system: which camera-side parameters the
// solve moves, and where they sit in the RCS (docs/design.md §2), made from
// the camera side's table of parameter blocks (problem/parameter_blocks.h).
//
// Block rows of the RCS, in this order:
//   1. every camera (image; with rigs, frame) that is not held fixed, in order:
//      9 unknowns (kBal) or a 6-unknown pose (kPhoto);
//   2. (kPhoto) every intrinsic group with at least one free parameter, in
//      group order: as many unknowns as it has free parameters (≤
//      kMaxIntrinsics).
//   3. (optional) the lever arm of the camera priors' antenna
//      (rcs/camera_centre_prior.h): 3 unknowns, the last row, touched by the
//      priors alone; its parameters are 3 more after the camera side's, at
//      x[num_parameters() - 3], stepped additively.
// Intrinsic rows come after the cameras, so a block (camera row, intrinsic
// row) is always in the stored upper triangle.
//
// With rigs (problem.h, docs/design.md §1.7) the camera rows are the frames
// that are not held (6 unknowns: rig_from_world), every image of a frame
// maps to its frame's row, and a group whose sensor pose is refined has 6
// more unknowns after its free intrinsics (sensor_from_rig). A step then
// moves the frames and the sensors, and the images' poses are composed
// anew from them. Fixed parameters are not unknowns: they have
// no row and no column, and a step never changes them.
//
// A step δ (one value per unknown) applies to the camera-side parameters x as
// x ⊞ δ: a camera row's first six unknowns step its pose (camera/pose_step.h:
// the rotation about the camera's centre, then the centre), as do a
// sensor's six; every other unknown j of row r adds,
// x[param_offset(r) + free_index(r, j)] += δ[row_offset(r) + j].
//
// Thread safety: immutable after construction.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "dba/problem/parameter_blocks.h"
#include "dba/problem/problem.h"

namespace dba {

class UnknownLayout {
 public:
  UnknownLayout() = default;
  explicit UnknownLayout(const CameraSide& side, bool lever_arm = false);
  // The rows of `blocks` (problem/parameter_blocks.h), the table of `side`.
  UnknownLayout(const CameraSide& side, const ParameterBlocks& blocks);

  int32_t num_block_rows() const { return static_cast<int32_t>(block_sizes_.size()); }
  int64_t num_unknowns() const { return row_offset_.back(); }
  int64_t num_parameters() const { return num_parameters_; }
  const std::vector<int32_t>& block_sizes() const { return block_sizes_; }
  int32_t block_size(int32_t r) const { return block_sizes_[r]; }
  int64_t row_offset(int32_t r) const { return row_offset_[r]; }
  int64_t param_offset(int32_t r) const { return param_offset_[r]; }

  // The images and intrinsic groups the layout was made for.
  int64_t num_images() const { return static_cast<int64_t>(camera_row_.size()); }
  int64_t num_groups() const { return static_cast<int64_t>(intrinsics_row_.size()); }
  // Block row of camera i (with rigs: of its frame) / intrinsic group g, or
  // -1 when held fixed.
  int32_t camera_row(int64_t i) const { return camera_row_[i]; }
  int32_t intrinsics_row(int64_t g) const {
    return intrinsics_row_.empty() ? -1 : intrinsics_row_[g];
  }
  // The block rows an observation of image i touches, each -1 when held
  // fixed: the image's camera row and (kPhoto) its intrinsic group's row.
  // `side` is the one this layout was made from. The RCS pattern, the
  // formation's shared rows and the point elimination read them here.
  struct ImageRows {
    int32_t camera;
    int32_t intrinsics;
  };
  ImageRows rows_of_image(const CameraSide& side, int64_t i) const {
    return {camera_row_[i], side.model == CameraModel::kPhoto
                                ? intrinsics_row(side.camera_intrinsics[i])
                                : -1};
  }
  // Rows [0, num_camera_rows()) are cameras, the rest intrinsic groups (and
  // the lever arm's, last).
  int32_t num_camera_rows() const { return num_camera_rows_; }
  // The lever arm's row, or -1 when it is not an unknown.
  int32_t lever_arm_row() const { return lever_arm_row_; }
  // Free parameter j of intrinsic group g, as an index into its
  // parameters (free parameters in increasing order).
  const std::array<int8_t, kMaxIntrinsics>& intrinsics_free_index(int64_t g) const {
    return free_index_[g];
  }
  // The largest intrinsics block (0 when there is none): the width the
  // kernels are instantiated for.
  int max_intrinsics_block() const { return max_intrinsics_block_; }

  // The intrinsics (not sensor) unknowns of intrinsics row r: its sensor
  // pose's six, if refined, follow them.
  int intrinsic_unknowns(int32_t r) const {
    return block_sizes_[r] - (sensor_offset_.empty() || sensor_offset_[row_entity_[r]] < 0 ? 0 : 6);
  }
  // Where unknown j of row r sits in x: param_offset(r) + j in a camera row
  // (whose unknowns 3-5 step the centre, not the t stored there), the
  // group's j-th free parameter in an intrinsics row, then its sensor pose.
  int64_t parameter_index(int32_t r, int j) const {
    if (r < num_camera_rows_ || r == lever_arm_row_) return param_offset_[r] + j;
    const int n = intrinsic_unknowns(r);
    return j < n ? param_offset_[r] + free_index_[row_entity_[r]][j]
                 : sensor_offset_[row_entity_[r]] + (j - n);
  }
  // out = x ⊞ δ (out may alias x).
  void Plus(const double* x, const double* delta, double* out) const;
  // The same over the camera side's parameters alone (x without the lever
  // arm's 3, which stay the LM's): what the points' workers step.
  void PlusCameraSide(const double* x, const double* delta, double* out) const;
  // Where a share's rows sit in the whole problem (distributed runs): for a
  // share whose camera (with rigs: frame) c is `global_camera[c]` and whose
  // group g is `global_intrinsics[g]` in the problem, each row's entity in
  // the problem's numbering: camera (frame) id i >= 0, or group g as -1 - g.
  std::vector<int64_t> RowEntities(const std::vector<int32_t>& global_camera,
                                   const std::vector<int32_t>& global_intrinsics) const;
  // This layout's rows of those entities; throws std::logic_error when an
  // entity has no row here.
  std::vector<int32_t> RowsOfEntities(const std::vector<int64_t>& entities) const;

 private:
  int64_t num_parameters_ = 0;
  int32_t num_camera_rows_ = 0;
  int32_t lever_arm_row_ = -1;
  int max_intrinsics_block_ = 0;
  std::vector<int32_t> camera_row_;
  std::vector<int32_t> intrinsics_row_;
  std::vector<std::array<int8_t, kMaxIntrinsics>> free_index_;
  std::vector<int32_t> block_sizes_;
  std::vector<int64_t> row_offset_{0};
  std::vector<int64_t> param_offset_;
  std::vector<int32_t> row_entity_;  // camera (frame) id, or group id
  // Rigs (empty without): per group where its refined sensor pose starts in
  // x (-1: none), and per image its frame and group, to compose the images.
  std::vector<int64_t> sensor_offset_;
  std::vector<int32_t> image_frame_, image_group_;
  std::vector<int32_t> frame_row_;  // rigs: each frame's row (-1: held)
  int64_t frames_offset_ = 0, sensors_offset_ = 0;

  int32_t AddRow(int size, int64_t param_offset, int32_t entity);
  void AddCameraRows(const CameraSide& side, const ParameterBlocks& blocks);
  void AddFrameRows(const CameraSide& side, const ParameterBlocks& blocks);
  void AddIntrinsicsRows(const CameraSide& side, const ParameterBlocks& blocks);
  void ComposeImages(double* x) const;
};

}  // namespace dba
