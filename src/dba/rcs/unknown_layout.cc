// Rows and sizes of the RCS unknowns; see unknown_layout.h.
#include "dba/rcs/unknown_layout.h"

#include "dba/camera/pose_step.h"
#include "dba/camera/rig_pose.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace dba {

UnknownLayout::UnknownLayout(const CameraSide& problem, bool lever_arm) {
  if (problem.num_frames() + problem.num_groups() > std::numeric_limits<int32_t>::max()) {
    // Block rows are 32-bit ids (docs/design.md §2).
    throw std::invalid_argument("more than 2^31 - 1 cameras and intrinsic groups");
  }
  num_parameters_ = static_cast<int64_t>(problem.cameras.size());
  if (problem.has_rigs()) {
    AddFrameRows(problem);
  } else {
    AddCameraRows(problem);
  }
  num_camera_rows_ = num_block_rows();
  AddIntrinsicsRows(problem);
  if (!lever_arm) return;
  lever_arm_row_ = num_block_rows();
  block_sizes_.push_back(3);
  param_offset_.push_back(num_parameters_);
  row_entity_.push_back(-1);
  row_offset_.push_back(row_offset_.back() + 3);
  num_parameters_ += 3;
}

void UnknownLayout::AddCameraRows(const CameraSide& problem) {
  const int64_t num_cameras = problem.num_images();
  const int cs = problem.camera_size();
  camera_row_.assign(num_cameras, -1);
  for (int64_t i = 0; i < num_cameras; ++i) {
    if (problem.camera_fixed(i)) continue;
    camera_row_[i] = static_cast<int32_t>(block_sizes_.size());
    block_sizes_.push_back(cs);
    param_offset_.push_back(cs * i);
    row_entity_.push_back(static_cast<int32_t>(i));
    row_offset_.push_back(row_offset_.back() + cs);
  }
}

// One row per frame none of whose images is held; each image on its frame's.
void UnknownLayout::AddFrameRows(const CameraSide& side) {
  const int64_t frames = side.num_frames();
  std::vector<uint8_t> held(frames, 0);
  for (int64_t i = 0; i < side.num_images(); ++i) {
    if (side.camera_fixed(i)) held[side.image_frame[i]] = 1;
  }
  std::vector<int32_t> frame_row(frames, -1);
  for (int64_t f = 0; f < frames; ++f) {
    if (held[f]) continue;
    frame_row[f] = static_cast<int32_t>(block_sizes_.size());
    block_sizes_.push_back(kPoseSize);
    param_offset_.push_back(side.frame_offset(f));
    row_entity_.push_back(static_cast<int32_t>(f));
    row_offset_.push_back(row_offset_.back() + kPoseSize);
  }
  frame_row_ = frame_row;
  camera_row_.resize(side.num_images());
  for (int64_t i = 0; i < side.num_images(); ++i) camera_row_[i] = frame_row[side.image_frame[i]];
  image_frame_ = side.image_frame;
  image_group_ = side.camera_intrinsics;
  frames_offset_ = side.frames_offset();
  sensors_offset_ = side.sensor_offset(0);
  sensor_offset_.assign(side.num_groups(), -1);
  for (int64_t g = 0; g < side.num_groups(); ++g) {
    if (side.sensor_kind[g] == kSensorRefined) sensor_offset_[g] = side.sensor_offset(g);
  }
}

void UnknownLayout::AddIntrinsicsRows(const CameraSide& problem) {
  const int64_t num_groups = problem.num_groups();
  intrinsics_row_.assign(num_groups, -1);
  free_index_.resize(num_groups);
  for (int64_t g = 0; g < num_groups; ++g) {
    const uint16_t mask = problem.intrinsics_free_mask(g);
    auto& index = free_index_[g];
    index.fill(-1);
    int n = 0;
    for (int d = 0; d < kMaxIntrinsics; ++d) {
      if (mask & (1u << d)) index[n++] = static_cast<int8_t>(d);
    }
    if (!sensor_offset_.empty() && sensor_offset_[g] >= 0) n += kPoseSize;
    if (n == 0) continue;
    if (n > kMaxIntrinsics) {
      throw std::invalid_argument(
          "intrinsic group " + std::to_string(g) + ": " + std::to_string(n - kPoseSize) +
          " free intrinsics and a refined sensor pose are more than " +
          std::to_string(kMaxIntrinsics) +
          " unknowns in one block; hold some intrinsics or the rig's geometry");
    }
    max_intrinsics_block_ = std::max(max_intrinsics_block_, n);
    intrinsics_row_[g] = static_cast<int32_t>(block_sizes_.size());
    block_sizes_.push_back(n);
    param_offset_.push_back(problem.intrinsics_offset(g));
    row_entity_.push_back(static_cast<int32_t>(g));
    row_offset_.push_back(row_offset_.back() + n);
  }
}

void UnknownLayout::Plus(const double* x, const double* delta, double* out) const {
  PlusCameraSide(x, delta, out);
  if (lever_arm_row_ < 0) return;
  const int64_t a = param_offset_[lever_arm_row_];
  for (int j = 0; j < 3; ++j) out[a + j] = x[a + j] + delta[row_offset_[lever_arm_row_] + j];
}

void UnknownLayout::PlusCameraSide(const double* x, const double* delta, double* out) const {
  const int64_t n = num_parameters_ - (lever_arm_row_ < 0 ? 0 : 3);
  if (out != x) std::copy(x, x + n, out);
  for (int32_t r = 0; r < num_block_rows(); ++r) {
    if (r == lever_arm_row_) continue;
    const double* d = delta + row_offset_[r];
    double* p = out + param_offset_[r];
    if (r < num_camera_rows_) {
      PlusPose(p, d, p);
      for (int j = kPoseSize; j < block_sizes_[r]; ++j) p[j] += d[j];
    } else {
      const int n = intrinsic_unknowns(r);
      for (int j = 0; j < n; ++j) out[parameter_index(r, j)] += d[j];
      if (n < block_sizes_[r]) {
        double* sensor = out + sensor_offset_[row_entity_[r]];
        PlusPose(sensor, d + n, sensor);
      }
    }
  }
  ComposeImages(out);
}

// With rigs, every image's pose = its sensor's ∘ its frame's.
void UnknownLayout::ComposeImages(double* x) const {
  if (image_frame_.empty()) return;
  const int64_t sensors = sensors_offset_;
  for (size_t i = 0; i < image_frame_.size(); ++i) {
    ComposeRigPose(x + sensors + kPoseSize * int64_t{image_group_[i]},
                   x + frames_offset_ + kPoseSize * int64_t{image_frame_[i]},
                   x + kPoseSize * static_cast<int64_t>(i));
  }
}

std::vector<int64_t> UnknownLayout::RowEntities(
    const std::vector<int32_t>& global_camera,
    const std::vector<int32_t>& global_intrinsics) const {
  std::vector<int64_t> entities(num_block_rows());
  for (int32_t r = 0; r < num_block_rows(); ++r) {
    const int32_t id = row_entity_[r];
    if (r == lever_arm_row_) {
      throw std::logic_error("UnknownLayout: the lever arm's row is not shared between ranks");
    }
    entities[r] = r < num_camera_rows_ ? int64_t{global_camera[id]}
                                       : -1 - int64_t{global_intrinsics[id]};
  }
  return entities;
}

std::vector<int32_t> UnknownLayout::RowsOfEntities(const std::vector<int64_t>& entities) const {
  std::vector<int32_t> rows(entities.size());
  for (size_t r = 0; r < entities.size(); ++r) {
    const int64_t e = entities[r];
    const int64_t g = -1 - e;
    const std::vector<int32_t>& by_id = image_frame_.empty() ? camera_row_ : frame_row_;
    rows[r] = e >= 0 ? (e < static_cast<int64_t>(by_id.size()) ? by_id[e] : -1)
                     : (g < static_cast<int64_t>(intrinsics_row_.size()) ? intrinsics_row_[g] : -1);
    if (rows[r] < 0) {
      throw std::logic_error("UnknownLayout: a share's unknown is not an unknown of the problem");
    }
  }
  return rows;
}

}  // namespace dba
