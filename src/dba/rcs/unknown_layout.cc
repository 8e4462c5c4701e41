// Rows and sizes of the RCS unknowns; see unknown_layout.h.
#include "dba/rcs/unknown_layout.h"

#include "dba/camera/pose_step.h"
#include "dba/camera/rig_pose.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace dba {

UnknownLayout::UnknownLayout(const CameraSide& side, bool lever_arm)
    : UnknownLayout(side, ParameterBlocks(side, lever_arm)) {}

UnknownLayout::UnknownLayout(const CameraSide& side, const ParameterBlocks& blocks) {
  if (side.num_frames() + side.num_groups() > std::numeric_limits<int32_t>::max()) {
    // Block rows are 32-bit ids (docs/design.md §2).
    throw std::invalid_argument("more than 2^31 - 1 cameras and intrinsic groups");
  }
  num_parameters_ = blocks.num_parameters();
  if (side.has_rigs()) {
    AddFrameRows(side, blocks);
  } else {
    AddCameraRows(side, blocks);
  }
  num_camera_rows_ = num_block_rows();
  AddIntrinsicsRows(side, blocks);
  if (blocks.lever_arm_block() < 0) return;
  lever_arm_row_ = AddRow(3, blocks[blocks.lever_arm_block()].offset, -1);
}

int32_t UnknownLayout::AddRow(int size, int64_t param_offset, int32_t entity) {
  block_sizes_.push_back(size);
  param_offset_.push_back(param_offset);
  row_entity_.push_back(entity);
  row_offset_.push_back(row_offset_.back() + size);
  return static_cast<int32_t>(block_sizes_.size()) - 1;
}

// One row per image whose block is free.
void UnknownLayout::AddCameraRows(const CameraSide& side, const ParameterBlocks& blocks) {
  camera_row_.assign(side.num_images(), -1);
  for (int64_t i = 0; i < side.num_images(); ++i) {
    const ParameterBlock& b = blocks[blocks.image_block(i)];
    if (b.free != 0) camera_row_[i] = AddRow(b.size, b.offset, static_cast<int32_t>(i));
  }
}

// One row per frame whose block is free (none of its images held); each
// image on its frame's.
void UnknownLayout::AddFrameRows(const CameraSide& side, const ParameterBlocks& blocks) {
  const int64_t frames = side.num_frames();
  frame_row_.assign(frames, -1);
  for (int64_t f = 0; f < frames; ++f) {
    const ParameterBlock& b = blocks[blocks.frame_block(f)];
    if (b.free != 0) frame_row_[f] = AddRow(b.size, b.offset, static_cast<int32_t>(f));
  }
  camera_row_.resize(side.num_images());
  for (int64_t i = 0; i < side.num_images(); ++i) camera_row_[i] = frame_row_[side.image_frame[i]];
  image_frame_ = side.image_frame;
  image_group_ = side.camera_intrinsics;
  frames_offset_ = frames > 0 ? blocks[blocks.frame_block(0)].offset : 0;
  sensors_offset_ = side.num_groups() > 0 ? blocks[blocks.sensor_block(0)].offset : 0;
  sensor_offset_.assign(side.num_groups(), -1);
  for (int64_t g = 0; g < side.num_groups(); ++g) {
    const ParameterBlock& b = blocks[blocks.sensor_block(g)];
    if (b.free != 0) sensor_offset_[g] = b.offset;
  }
}

// One row per group with a free intrinsic or a refined sensor pose: its
// free intrinsics, then the pose's six.
void UnknownLayout::AddIntrinsicsRows(const CameraSide& side, const ParameterBlocks& blocks) {
  const int64_t num_groups = side.num_groups();
  intrinsics_row_.assign(num_groups, -1);
  free_index_.resize(num_groups);
  for (int64_t g = 0; g < num_groups; ++g) {
    const ParameterBlock& b = blocks[blocks.group_block(g)];
    auto& index = free_index_[g];
    index.fill(-1);
    int n = 0;
    for (int d = 0; d < kMaxIntrinsics; ++d) {
      if (b.free & (1u << d)) index[n++] = static_cast<int8_t>(d);
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
    intrinsics_row_[g] = AddRow(n, b.offset, static_cast<int32_t>(g));
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
