// Extraction of a rank's share; see rank_share.h.
#include "dba/cluster/rank_share.h"

#include <algorithm>
#include <numeric>

#include "dba/problem/point_order.h"

namespace dba {

RankShare ExtractShare(const Problem& full, std::span<const int32_t> point_group,
                       int32_t group) {
  RankShare s;
  Problem& p = s.problem;
  p.model = full.model;
  p.intrinsics_size = full.intrinsics_size;
  p.group_models = full.group_models;
  p.cameras = full.cameras;
  p.camera_intrinsics = full.camera_intrinsics;
  p.fixed_cameras = full.fixed_cameras;
  p.fixed_intrinsics = full.fixed_intrinsics;
  p.image_frame = full.image_frame;
  p.sensor_kind = full.sensor_kind;
  p.point_offsets.push_back(0);
  for (int64_t k = 0; k < full.num_points(); ++k) {
    if (point_group[k] != group) continue;
    if (const PointPrior* prior = full.point_prior(k)) {
      p.point_priors.push_back(*prior);
      p.point_priors.back().point = p.num_points();
    }
    s.global_point.push_back(k);
    p.points.insert(p.points.end(), full.point(k), full.point(k) + kPointSize);
    for (int64_t o = full.point_offsets[k]; o < full.point_offsets[k + 1]; ++o) {
      p.obs_camera.push_back(full.obs_camera[o]);
      p.obs_pixel.push_back(full.obs_pixel[2 * o]);
      p.obs_pixel.push_back(full.obs_pixel[2 * o + 1]);
    }
    p.point_offsets.push_back(p.num_observations());
  }
  KeepTouchedCameras(&s);
  return s;
}

namespace {

// Rigs: the frames of the share's images (in increasing order) and the
// sensors of its groups, after the groups in `cameras`.
void KeepTouchedFrames(const Problem& old, RankShare* share) {
  Problem& p = share->problem;
  std::vector<int32_t> local_frame(old.num_frames(), -1);
  for (int32_t c : share->global_camera) local_frame[old.image_frame[c]] = 0;
  share->global_frame.clear();
  for (int64_t f = 0; f < old.num_frames(); ++f) {
    if (local_frame[f] < 0) continue;
    local_frame[f] = static_cast<int32_t>(share->global_frame.size());
    share->global_frame.push_back(static_cast<int32_t>(f));
    const double* pose = old.cameras.data() + old.frame_offset(f);
    p.cameras.insert(p.cameras.end(), pose, pose + kPhotoPoseSize);
  }
  for (int32_t g : share->global_intrinsics) {
    const double* pose = old.cameras.data() + old.sensor_offset(g);
    p.cameras.insert(p.cameras.end(), pose, pose + kPhotoPoseSize);
    p.sensor_kind.push_back(old.sensor_kind[g]);
  }
  for (int32_t c : share->global_camera) p.image_frame.push_back(local_frame[old.image_frame[c]]);
}

// The touched cameras, intrinsic groups (and frames) in increasing order.
void KeepTouchedInOrder(RankShare* share) {
  Problem& p = share->problem;
  Problem old;  // the camera side as it was
  old.model = p.model;
  old.intrinsics_size = p.intrinsics_size;
  old.cameras.swap(p.cameras);
  old.group_models.swap(p.group_models);
  old.camera_intrinsics.swap(p.camera_intrinsics);
  old.fixed_cameras.swap(p.fixed_cameras);
  old.fixed_intrinsics.swap(p.fixed_intrinsics);
  old.image_frame.swap(p.image_frame);
  old.sensor_kind.swap(p.sensor_kind);
  const bool photo = old.model == CameraModel::kPhoto;
  std::vector<int32_t> local_camera(old.num_images(), -1);
  std::vector<int32_t> local_group(old.num_groups(), -1);
  for (int32_t c : p.obs_camera) local_camera[c] = 0;
  share->global_camera.clear();
  share->global_intrinsics.clear();
  for (int64_t i = 0; i < old.num_images(); ++i) {
    if (local_camera[i] < 0) continue;
    local_camera[i] = static_cast<int32_t>(share->global_camera.size());
    share->global_camera.push_back(static_cast<int32_t>(i));
    p.cameras.insert(p.cameras.end(), old.camera(i), old.camera(i) + old.camera_size());
    if (!old.fixed_cameras.empty()) p.fixed_cameras.push_back(old.fixed_cameras[i]);
    if (photo) local_group[old.camera_intrinsics[i]] = 0;
  }
  for (int32_t& c : p.obs_camera) c = local_camera[c];
  if (!photo) return;
  for (int64_t g = 0; g < old.num_groups(); ++g) {
    if (local_group[g] < 0) continue;
    local_group[g] = static_cast<int32_t>(share->global_intrinsics.size());
    share->global_intrinsics.push_back(static_cast<int32_t>(g));
    p.cameras.insert(p.cameras.end(), old.intrinsics(g),
                     old.intrinsics(g) + old.intrinsics_size);
    if (!old.group_models.empty()) p.group_models.push_back(old.group_models[g]);
    if (!old.fixed_intrinsics.empty()) p.fixed_intrinsics.push_back(old.fixed_intrinsics[g]);
  }
  for (int32_t c : share->global_camera) {
    p.camera_intrinsics.push_back(local_group[old.camera_intrinsics[c]]);
  }
  if (old.has_rigs()) KeepTouchedFrames(old, share);
}

// A walked share's cameras (local ids) as its walk first sees them; with
// rigs the frames number the rows, and the cameras keep their order.
void NumberCamerasByWalk(RankShare* share) {
  if (share->problem.has_rigs()) return;
  const std::vector<int64_t> cameras = CamerasInPointOrder(share->problem);
  PermuteCameras(cameras, &share->problem);
  std::vector<int32_t> camera(cameras.size());
  for (size_t k = 0; k < cameras.size(); ++k) camera[k] = share->global_camera[cameras[k]];
  share->global_camera.swap(camera);
}

}  // namespace

void KeepTouchedCameras(RankShare* share) {
  KeepTouchedInOrder(share);
  if (share->walked) NumberCamerasByWalk(share);
}

void WalkShare(RankShare* share, std::span<const int64_t> place) {
  std::vector<int64_t> walk;
  if (place.empty()) {
    walk = PointWalk(share->problem);
  } else {
    walk.resize(share->global_point.size());
    std::iota(walk.begin(), walk.end(), int64_t{0});
    std::sort(walk.begin(), walk.end(), [&](int64_t a, int64_t b) {
      return place[share->global_point[a]] < place[share->global_point[b]];
    });
  }
  if (walk.empty()) return;
  PermutePoints(walk, &share->problem);
  std::vector<int64_t> point(walk.size());
  for (size_t k = 0; k < walk.size(); ++k) point[k] = share->global_point[walk[k]];
  share->global_point.swap(point);
  share->walked = true;
  if (!share->global_camera.empty()) NumberCamerasByWalk(share);  // ids local already
}

}  // namespace dba
