// One rank's share of a problem (docs/design.md §4): its points, their
// observations and priors, and the cameras (and intrinsic groups) they
// touch, renumbered locally: in increasing global order, or a walked share's
// cameras in its walk's (WalkShare).
//
// Thread safety: pure function.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "dba/problem/problem.h"

namespace dba {

struct RankShare {
  Problem problem;                     // local camera and group ids
  std::vector<int32_t> global_camera;     // local camera -> global camera
  std::vector<int32_t> global_intrinsics; // local group -> global group (kPhoto)
  std::vector<int64_t> global_point;      // local point -> global point
  std::vector<int32_t> global_frame;      // rigs: local frame -> global frame
  bool walked = false;                    // its points in their walk (WalkShare)
  // What a camera row of the share's layout stands for, globally: its
  // camera, or with rigs its frame (UnknownLayout::RowEntities).
  const std::vector<int32_t>& CameraRowIds() const {
    return problem.has_rigs() ? global_frame : global_camera;
  }
};

// The points with point_group[k] == group, in global order, with only the
// cameras they touch (KeepTouchedCameras done: not to be done again, the
// share's camera ids are local then).
RankShare ExtractShare(const Problem& full, std::span<const int32_t> point_group,
                       int32_t group);

// Keeps only the cameras that `share.problem`'s observations touch (and
// their intrinsic groups and, with rigs, their frames), renumbered in
// increasing order (a walked share's cameras then in its walk's, WalkShare); fills global_camera, global_intrinsics (and
// global_frame) with the old ids. For a share whose
// camera ids are global (one read from a .dba); ExtractShare's are not.
void KeepTouchedCameras(RankShare* share);

// The share's points in the walk one process takes over a problem
// (problem/point_order.h's PointWalk), and its cameras numbered as the walk
// first sees them (CamerasInPointOrder; with rigs they keep their order;
// a share read with global camera ids is numbered so by KeepTouchedCameras);
// global_point and global_camera follow. A share whose order is local
// already keeps it. Each rank walks its own share once, before its first
// workers: a shuffled input then forms its sub-RCS about as fast as an
// ordered one. A walked share's block (i, j), i ≤ j, can be the global
// RCS's (global_camera[j], global_camera[i]): it is sent transposed
// (cluster/block_transfer.h). `place` (global point -> its place in a walk
// over the whole problem, the one taken at the load): the share's points in
// that walk's order instead, whatever their positions now (a resumed solve
// orders them as the uninterrupted one did).
void WalkShare(RankShare* share, std::span<const int64_t> place = {});

}  // namespace dba
