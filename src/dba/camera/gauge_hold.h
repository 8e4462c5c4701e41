// The gauge of a bundle: its cost does not change when a similarity of the
// world (rotation, translation, scale: 7 degrees of freedom) moves every
// camera and point (camera/pose_similarity.h), so an optimum is a family
// and LM ends at whichever member its path meets. What nothing else holds
// (camera priors or control points, images held fixed) is held here by
// mapping the optimum back onto the input's frame:
//
//   anchor A (the first image, or the first image held fixed), second B
//   (the first image whose centre is away from A's, as loaded; with rigs,
//   the first of A's sensor in another frame: with A the rig's origin, the
//   first frame's pose and the distance between two frames' origins; a
//   held sensor away from its rig's origin holds the scale, and then only
//   A's pose is kept)
//   X' = s Q X + T   with  Q = R_A,inᵀ R_A,   s = |C_B,in − C_A,in| / |C_B − C_A|,
//                         T = R_A,inᵀ (s t_A − t_A,in)
//
// so A keeps its input pose and the distance A-B its input value; the
// reprojection errors, the cost and the robust weights are unchanged.
// With an image held fixed only the scale is free: Q = I, T = (1 − s) C_A.
// Two fixed images with distinct centres, camera priors or control points
// hold all 7 and nothing moves.
//
// Thread safety: pure functions (MoveBundle writes its arguments).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dba/camera/pose_similarity.h"
#include "dba/problem/problem.h"

namespace dba {

enum class GaugeHold {
  kFree,          // --gauge free: the optimum LM ended at
  kExternal,      // camera priors or control points hold it
  kFixedImages,   // two fixed images with distinct centres hold it
  kFixedImage,    // one fixed image holds pose; its distance to `second` holds scale
  kFirstImage,    // `anchor`'s pose and its distance to `second` are kept
};

struct GaugeReference {
  GaugeHold hold = GaugeHold::kFree;
  int64_t anchor = -1;             // the image whose pose is kept
  int64_t second = -1;             // -1: every centre at the anchor's (scale left free)
  std::array<double, 6> pose{};    // the anchor's pose as loaded (ω, t)
  double distance = 0.0;           // |C_second − C_anchor| as loaded
  bool rig_scale = false;          // a held sensor's place holds the scale
};

// What holds the gauge of `side` as loaded; `external`: priors or control
// points hold it. Images with a centre within 1e-12 of the spread of the
// centres of the anchor's count as at the anchor.
GaugeReference TakeGaugeReference(const CameraSide& side, bool external);

// The similarity bringing the solved `side` back onto the reference's frame
// (the identity when nothing is to be held, or the solve moved a fixed
// anchor's partner onto it; exactly the identity when the anchor and its
// distance are bit for bit as taken, so an unmoved model is not rewritten).
Similarity GaugeMapping(const GaugeReference& ref, const CameraSide& side);

// Moves every image that is not held fixed by `s`; the anchor is then
// given its input pose exactly.
void MoveCameras(const Similarity& s, const GaugeReference& ref, CameraSide* side);
// Moves the points (kPointSize per point) whose flag in `moved` is set
// (every point when `moved` is empty) by `s`.
void MovePoints(const Similarity& s, std::vector<double>* points,
                const std::vector<uint8_t>& moved = {});

// "the first image (0) and its distance to image 3", "two fixed images", ...
std::string DescribeGauge(const GaugeReference& ref, const Similarity& moved_by);

}  // namespace dba
