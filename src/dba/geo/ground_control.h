// Ground control and check points in a solve (the surveyed points of
// io/ground_control_file.h, their images resolved):
//
//   control points  3D points of the solve with a prior on their coordinates
//                   (problem.h's PointPrior, r = (X - X_survey)/σ per axis),
//                   appended after the problem's own points, with their
//                   image measurements as observations; eliminated like any
//                   point;
//   check points    never in the solve: triangulated afterwards from the
//                   adjusted cameras and compared with their surveyed
//                   coordinates.
//
// Triangulation: X minimizing Σ |r_a(X)|² over the point's measurements,
// with the cameras held fixed (Levenberg–Marquardt on 3 unknowns, central
// differences), started from each measurement's nearest tie point (the
// problem's observed pixel closest to it in that image), the best kept: no
// ray casting, so every lens model works alike.
//
// Thread safety: pure functions but AddControlPoints/RemoveControlPoints,
// which write *problem.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dba/geo/prior_alignment.h"
#include "dba/problem/problem.h"

namespace dba {

struct GroundControlPoint {
  std::string name;
  Vec3 position = Vec3::Zero();  // surveyed, in the solve's frame
  Vec3 sigma = Vec3::Ones();     // per axis X, Y, Z
  bool control = true;           // else a check point
  struct Measurement {
    int32_t image = 0;
    Vec2 pixel = Vec2::Zero();
  };
  std::vector<Measurement> measurements;
};

struct GroundControl {
  std::vector<GroundControlPoint> points;
  bool empty() const { return points.empty(); }
  int64_t CountControl() const;
};

struct Triangulation {
  Vec3 X = Vec3::Zero();
  double rms_px = 0.0;  // RMS of |r_a| at X
  bool ok = false;      // converged to a finite point
};

// Each point of `gcps` with `control` == `which` triangulated from
// `problem`'s cameras, in order. Starts: the nearest tie points (when the
// problem holds its observations), and with `start_at_survey` the surveyed
// position (once the block is in the survey's frame).
std::vector<Triangulation> TriangulateGroundControl(const Problem& problem,
                                                    const GroundControl& gcps, bool which,
                                                    bool start_at_survey);

// The similarity from triangulated control points onto their surveyed
// positions (RANSAC + Umeyama, geo/prior_alignment.h), for a block without
// camera priors. Throws std::invalid_argument for fewer than 3 triangulated
// control points.
SimilarityFit AlignToControlPoints(const GroundControl& gcps,
                                   const std::vector<Triangulation>& triangulated);

// Appends the control points to `problem`, each starting at its surveyed
// position, with its measurements as observations and its prior.
void AddControlPoints(const GroundControl& gcps, Problem* problem);

// Removes the last `count` points (the control points AddControlPoints
// appended, which every later step keeps last) with their observations (if
// the problem holds them) and priors; returns their adjusted coordinates, 3
// per point.
std::vector<double> RemoveControlPoints(int64_t count, Problem* problem);

}  // namespace dba
