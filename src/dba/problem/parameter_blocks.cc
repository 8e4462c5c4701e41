// The camera side's parameter blocks; see parameter_blocks.h.
#include "dba/problem/parameter_blocks.h"

namespace dba {
namespace {

constexpr uint32_t AllOf(int size) { return (uint32_t{1} << size) - 1; }

// With rigs: a frame is held when one of its images is.
std::vector<uint8_t> HeldFrames(const CameraSide& side) {
  std::vector<uint8_t> held(side.num_frames(), 0);
  for (int64_t i = 0; i < side.num_images(); ++i) {
    if (side.camera_fixed(i)) held[side.image_frame[i]] = 1;
  }
  return held;
}

}  // namespace

const char* BlockKindName(BlockKind kind) {
  switch (kind) {
    case BlockKind::kBalCamera: return "bal_cameras";
    case BlockKind::kImagePose: return "image_poses";
    case BlockKind::kIntrinsics: return "intrinsics";
    case BlockKind::kFramePose: return "frame_poses";
    case BlockKind::kSensorPose: return "sensor_poses";
    case BlockKind::kLeverArm: return "lever_arm";
  }
  return "?";
}

void ParameterBlocks::Add(BlockKind kind, BlockScope scope, BlockStep step, int32_t size,
                          int64_t entity, uint32_t free) {
  blocks_.push_back({kind, scope, step, size, entity, num_parameters_, free});
  num_parameters_ += size;
}

ParameterBlocks::ParameterBlocks(const CameraSide& side, bool lever_arm) {
  const bool bal = side.model == CameraModel::kBal;
  const bool rigs = side.has_rigs();
  const int size = side.camera_size();
  const uint32_t pose = AllOf(size);
  blocks_.reserve(side.num_images() + side.num_groups() + (rigs ? side.num_frames() + side.num_groups() : 0) + 1);
  for (int64_t i = 0; i < side.num_images(); ++i) {
    if (rigs) {
      Add(BlockKind::kImagePose, BlockScope::kImage, BlockStep::kComposed, size, i, 0);
    } else {
      Add(bal ? BlockKind::kBalCamera : BlockKind::kImagePose, BlockScope::kImage,
          BlockStep::kPose, size, i, side.camera_fixed(i) ? 0 : pose);
    }
  }
  first_group_ = static_cast<int64_t>(blocks_.size());
  for (int64_t g = 0; g < side.num_groups(); ++g) {
    Add(BlockKind::kIntrinsics, BlockScope::kGroup, BlockStep::kAdd, side.intrinsics_size, g,
        side.intrinsics_free_mask(g));
  }
  if (rigs) {
    const std::vector<uint8_t> held = HeldFrames(side);
    first_frame_ = static_cast<int64_t>(blocks_.size());
    for (int64_t f = 0; f < side.num_frames(); ++f) {
      Add(BlockKind::kFramePose, BlockScope::kFrame, BlockStep::kPose, kPhotoPoseSize, f,
          held[f] ? 0 : AllOf(kPhotoPoseSize));
    }
    first_sensor_ = static_cast<int64_t>(blocks_.size());
    for (int64_t g = 0; g < side.num_groups(); ++g) {
      Add(BlockKind::kSensorPose, BlockScope::kGroup, BlockStep::kPose, kPhotoPoseSize, g,
          side.sensor_kind[g] == kSensorRefined ? AllOf(kPhotoPoseSize) : 0);
    }
  }
  if (lever_arm) {
    lever_arm_ = static_cast<int64_t>(blocks_.size());
    Add(BlockKind::kLeverArm, BlockScope::kProblem, BlockStep::kAdd, 3, 0, AllOf(3));
  }
}

int64_t ParameterBlocks::num_unknowns() const {
  int64_t n = 0;
  for (const ParameterBlock& b : blocks_) n += b.num_free();
  return n;
}

int64_t ParameterBlocks::num_unknowns(BlockKind kind) const {
  int64_t n = 0;
  for (const ParameterBlock& b : blocks_) n += b.kind == kind ? b.num_free() : 0;
  return n;
}

}  // namespace dba
