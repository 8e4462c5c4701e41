// Rigs for the synthetic UAV survey (`dba generate --rig`): the
// sensors of a named rig, their true poses (the nominal ones with small
// manufacturing errors, so refining them matters), and the survey's camera
// side with one frame per exposure.
//
// Rigs, each given first about a nadir rig frame N (COLMAP's axes: x right,
// y down, z to the ground), then re-expressed about its first sensor, the
// rig's origin (sensor_from_rig = S_s|N ∘ S_0|N⁻¹, rig_from_world =
// S_0|N ∘ N_from_world):
//   oblique5  a nadir camera and four 45° obliques (fore, aft, left, right),
//             10 cm from it
//   stereo    two nadir cameras 60 cm apart
//   ring6     six cameras tilted 45° every 60° about the vertical, on a
//             15 cm ring
// Truth: each sensor turned by ~0.3° and moved by ~1 cm (σ, per axis) from
// the nominal; the initial sensor poses are the nominal ones.
//
// Thread safety: pure functions.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dba/problem/problem.h"

namespace dba {

using Pose6 = std::array<double, 6>;  // (ω, t), world (or rig) -> camera

struct RigSensors {
  std::vector<Pose6> nominal;  // sensor_from_rig, the first the identity
  std::vector<Pose6> truth;
  // The first sensor about the nadir frame N (rig_from_world = it ∘ N).
  Pose6 nominal_first{}, truth_first{};
  // Per sensor, the share of its ground footprint's points it keeps, so that
  // an oblique's observations per image are about a nadir's.
  std::vector<double> keep;
  // How far (metres, horizontally) from its frame's nadir point a sensor sees.
  double reach = 0.0;
};

// How many sensors the named rig has; std::invalid_argument for an unknown
// name.
int64_t RigSensorCount(const std::string& name);

// Throws std::invalid_argument for an unknown name.
RigSensors MakeRigSensors(const std::string& name, uint64_t seed, double flying_height,
                          double focal_px, double image_size);

// The survey's camera side with rigs from per-frame nadir poses (`nadir`:
// a kPhoto side, one image per frame, groups by strip as without rigs):
// images f · S + s, sensor s the group s (its intrinsics those of the
// nadir side's group min(s, groups - 1)), frames at first ∘ nadir, the
// sensors `sensors`, the images composed.
Problem RigCameraSide(const Problem& nadir, const std::vector<Pose6>& sensors, const Pose6& first);

}  // namespace dba
