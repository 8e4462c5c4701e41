// The camera side's parameters as a table of blocks (docs/design.md §1.8):
// every image's BAL camera or pose, intrinsic group, rig frame and sensor
// pose, and the camera priors' lever arm, one entry each, in the order their
// parameters follow each other in the parameter vector (CameraSide::cameras,
// then the lever arm's 3: the LM's x). Each block has
//
//   kind    what its parameters mean (which Jacobian moves it)
//   scope   what it belongs to: an image, an intrinsic group, a frame, or
//           the whole problem (entity: the image, group or frame; 0)
//   size    its parameters, from `offset` on in the parameter vector
//   step    how a step δ moves it (⊞): kPose, the rotation about the
//           centre then the centre on its first six (camera/pose_step.h),
//           the rest added; kAdd, added; kComposed, none of its own (a rig
//           image's pose, composed from its frame's and sensor's)
//   free    bit j: parameter j is an unknown (0: the block is held)
//
// UnknownLayout (rcs/unknown_layout.h) makes the RCS's rows from the table;
// the reports count the unknowns by kind from it.
//
// Thread safety: immutable after construction.
#pragma once

#include <bit>
#include <cstdint>
#include <vector>

#include "dba/problem/problem.h"

namespace dba {

enum class BlockKind : uint8_t {
  kBalCamera,   // ω, t, f, k1, k2 of a BAL image
  kImagePose,   // ω, t of a photogrammetric image
  kIntrinsics,  // an intrinsic group's lens parameters (intrinsics_size slots)
  kFramePose,   // a rig frame's rig_from_world
  kSensorPose,  // a rig sensor's sensor_from_rig
  kLeverArm,    // the camera priors' antenna in the camera's (rig's) frame
};
inline constexpr int kNumBlockKinds = 6;
const char* BlockKindName(BlockKind kind);

enum class BlockScope : uint8_t { kImage, kGroup, kFrame, kProblem };
enum class BlockStep : uint8_t { kPose, kAdd, kComposed };

struct ParameterBlock {
  BlockKind kind;
  BlockScope scope;
  BlockStep step;
  int32_t size;
  int64_t entity;
  int64_t offset;
  uint32_t free;
  int num_free() const { return std::popcount(free); }
};

class ParameterBlocks {
 public:
  // The blocks of `side`; `lever_arm`: and the lever arm's, 3 parameters
  // after the camera side's.
  explicit ParameterBlocks(const CameraSide& side, bool lever_arm = false);

  const std::vector<ParameterBlock>& blocks() const { return blocks_; }
  const ParameterBlock& operator[](int64_t b) const { return blocks_[b]; }
  int64_t num_parameters() const { return num_parameters_; }
  // The unknowns (free parameters), over every block and by kind.
  int64_t num_unknowns() const;
  int64_t num_unknowns(BlockKind kind) const;

  // Where each entity's block is in blocks() (-1: none): image i, group g's
  // intrinsics, frame f (rigs), group g's sensor pose (rigs), the lever arm.
  int64_t image_block(int64_t i) const { return i; }
  int64_t group_block(int64_t g) const { return first_group_ + g; }
  int64_t frame_block(int64_t f) const { return first_frame_ < 0 ? -1 : first_frame_ + f; }
  int64_t sensor_block(int64_t g) const { return first_sensor_ < 0 ? -1 : first_sensor_ + g; }
  int64_t lever_arm_block() const { return lever_arm_; }

 private:
  std::vector<ParameterBlock> blocks_;
  int64_t num_parameters_ = 0;
  int64_t first_group_ = 0, first_frame_ = -1, first_sensor_ = -1, lever_arm_ = -1;
  void Add(BlockKind kind, BlockScope scope, BlockStep step, int32_t size, int64_t entity,
           uint32_t free);
};

}  // namespace dba
