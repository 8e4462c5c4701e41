// Tests of ProblemFromColmap / UpdateColmapModel on the five shared COLMAP
// models: the unchanged problem written back reproduces each model, the
// reprojection error at COLMAP's own solution is small and agrees with the
// points' `error` fields, observation and group counts, fixed images and
// intrinsics, refused camera models and ids, and the write-back of per-image
// intrinsics (new camera ids) and of changed parameters.
#include "dba/io/colmap_problem.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "dba/camera/photo_camera.h"
#include "dba/common/error.h"
#include "dba/io/colmap_binary.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

const char* const kModels[] = {"statue_of_liberty", "statue_of_liberty_small_txt",
                               "fountain_p11", "softmurata_177img", "mithunnallana_6img"};

std::string SharedDir(const std::string& folder) {
  return std::string(DBA_SHARED_DATA_DIR) + "/colmap/" + folder + "/sparse/0";
}

// Runs `f`, expecting an InputError whose message contains every one of
// `phrases`.
template <typename F>
void ExpectInputError(F f, const std::vector<std::string>& phrases) {
  try {
    f();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string& p : phrases) {
      EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
    }
    return;
  }
  ADD_FAILURE() << "no InputError";
}

// Reprojection error |r| (pixels) of every observation.
std::vector<double> ObservationErrors(const Problem& p) {
  std::vector<double> e(p.num_observations());
  for (int64_t k = 0; k < p.num_points(); ++k) {
    for (int64_t o = p.point_offsets[k]; o < p.point_offsets[k + 1]; ++o) {
      const int32_t i = p.obs_camera[o];
      const int32_t g = p.camera_intrinsics[i];
      e[o] = PhotoResidual(p.group_model(g), p.camera(i), p.intrinsics(g), p.point(k), p.pixel(o))
                 .norm();
    }
  }
  return e;
}

// The normalised quaternion with qw >= 0.
std::array<double, 4> Canonical(std::array<double, 4> q) {
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  const double s = q[0] < 0 ? -1.0 / n : 1.0 / n;
  for (double& x : q) x *= s;
  return q;
}

// Two SIMPLE_RADIAL cameras (ids 7 and 2); images 3 and 5 share camera 7,
// image 9 uses camera 2, image 11 (camera 7) sees only a one-view point.
ColmapModel SmallModel() {
  ColmapModel m;
  m.cameras.push_back({7, 2, 640, 480, {500, 320, 240, -0.1}});
  m.cameras.push_back({2, 2, 800, 600, {600, 400, 300, 0.05}});
  ColmapImage a;
  a.image_id = 3;
  a.qvec = {0.9, 0.1, -0.2, 0.3};  // not unit
  a.tvec = {0.1, 0.2, 0.3};
  a.camera_id = 7;
  a.name = "a.jpg";
  a.points2D = {{300, 200, 100}, {30, 40, kColmapNoPoint3D}, {350, 250, 101}};
  ColmapImage b;
  b.image_id = 5;
  b.qvec = {-1, 0, 0, 0};
  b.tvec = {1, 0, 0};
  b.camera_id = 7;
  b.name = "b.jpg";
  b.points2D = {{420, 230, 101}, {330, 250, 100}};
  ColmapImage c = b;
  c.image_id = 9;
  c.camera_id = 2;
  c.name = "c.jpg";
  c.tvec = {0, 1, 0};
  c.points2D = {{410, 190, 100}};
  ColmapImage d = b;
  d.image_id = 11;
  d.camera_id = 7;
  d.name = "d.jpg";
  d.points2D = {{100, 100, 102}};
  m.images = {d, a, b, c};
  m.points3D.push_back({100, {0, 0, 5}, {255, 0, 0}, 0.5, {{3, 0}, {5, 1}, {9, 0}}});
  m.points3D.push_back({102, {3, 3, 9}, {1, 2, 3}, 0.125, {{11, 0}}});
  m.points3D.push_back({101, {1, 0, 5}, {0, 255, 0}, 0.25, {{3, 2}, {5, 0}}});
  ValidateColmapModel(m, "small", ".txt");
  return m;
}

TEST(ColmapProblemTest, UnchangedProblemReproducesEveryModel) {
  for (const char* folder : kModels) {
    SCOPED_TRACE(folder);
    const ColmapModel original = ReadColmapModel(SharedDir(folder));
    std::set<uint32_t> used_cameras;
    for (const ColmapImage& im : original.images) used_cameras.insert(im.camera_id);
    for (bool shared : {true, false}) {
      // Per-image groups write back to the same cameras only when no two
      // images share one (see PerImageWriteBackCreatesNewCameras otherwise).
      if (!shared && used_cameras.size() < original.images.size()) continue;
      SCOPED_TRACE(shared ? "shared intrinsics" : "per-image intrinsics");
      ColmapProblemOptions options;
      options.shared_intrinsics = shared;
      const ColmapProblem cp = ProblemFromColmap(original, options, SharedDir(folder));
      ColmapModel m = original;
      UpdateColmapModel(cp, cp.problem, &m);
      ASSERT_EQ(m.cameras.size(), original.cameras.size());  // no image had to be split off
      ASSERT_EQ(m.images.size(), original.images.size());
      ASSERT_EQ(m.points3D.size(), original.points3D.size());
      // Quaternions: the normalised original, up to sign, to 1e-12.
      double max_q = 0, max_norm_dev = 0;
      for (size_t j = 0; j < m.images.size(); ++j) {
        const auto a = Canonical(original.images[j].qvec);
        const auto& b = m.images[j].qvec;
        EXPECT_GE(b[0], 0.0);
        double norm2 = 0;
        for (int d = 0; d < 4; ++d) {
          max_q = std::max(max_q, std::abs(a[d] - b[d]));
          norm2 += original.images[j].qvec[d] * original.images[j].qvec[d];
        }
        max_norm_dev = std::max(max_norm_dev, std::abs(std::sqrt(norm2) - 1));
        m.images[j].qvec = original.images[j].qvec;
      }
      EXPECT_LE(max_q, 1e-12);
      if (shared) {
        std::cout << "  " << folder << ": max | |q| - 1 | in the file " << max_norm_dev
                  << ", max quaternion change after the round trip " << max_q << "\n";
      }
      // Errors of adjusted points are recomputed (checked in ReprojectionError...).
      for (int64_t k : cp.point_index) m.points3D[k].error = original.points3D[k].error;
      // Everything else bit for bit: names, ids, colours, tracks, 2D points,
      // tvec, xyz, camera params.
      EXPECT_EQ(FirstColmapModelDifference(original, m), "");
    }
  }
}

TEST(ColmapProblemTest, ReprojectionErrorAtColmapsSolutionIsSmall) {
  // RMS = sqrt(mean over observations of |r|^2), |r| the pixel distance
  // between the projection and the observed 2D point (so per residual
  // component it is RMS / sqrt(2)). COLMAP's `error` of a point is the mean
  // of |r| over its track; we compare the mean of those over the kept points
  // with the same quantity computed here.
  for (const char* folder : kModels) {
    SCOPED_TRACE(folder);
    const ColmapModel model = ReadColmapModel(SharedDir(folder));
    const ColmapProblem cp = ProblemFromColmap(model, {}, SharedDir(folder));
    const Problem& p = cp.problem;
    const std::vector<double> e = ObservationErrors(p);
    double sum2 = 0, max_e = 0;
    for (double x : e) sum2 += x * x, max_e = std::max(max_e, x);
    const double rms = std::sqrt(sum2 / static_cast<double>(e.size()));
    double ours = 0, colmap = 0, max_point_diff = 0;
    for (int64_t k = 0; k < p.num_points(); ++k) {
      double s = 0;
      for (int64_t o = p.point_offsets[k]; o < p.point_offsets[k + 1]; ++o) s += e[o];
      const double mean = s / static_cast<double>(p.point_offsets[k + 1] - p.point_offsets[k]);
      ours += mean;
      colmap += model.points3D[cp.point_index[k]].error;
      max_point_diff = std::max(max_point_diff, std::abs(mean - model.points3D[cp.point_index[k]].error));
    }
    ours /= static_cast<double>(p.num_points());
    colmap /= static_cast<double>(p.num_points());
    std::cout << "  " << folder << ": RMS reprojection error " << rms << " px over "
              << e.size() << " observations (max " << max_e << "); mean point error "
              << ours << " px, COLMAP's error field " << colmap
              << " (max difference per point " << max_point_diff << ")\n";
    RecordProperty(std::string(folder) + "_rms_px", std::to_string(rms));
    RecordProperty(std::string(folder) + "_mean_point_error_px", std::to_string(ours));
    RecordProperty(std::string(folder) + "_colmap_mean_error_px", std::to_string(colmap));
    EXPECT_LT(rms, 2.0);
    EXPECT_NEAR(ours, colmap, 0.05 + 0.05 * colmap);

    // UpdateColmapModel writes exactly these per-point means.
    ColmapModel m = model;
    UpdateColmapModel(cp, p, &m);
    for (int64_t k = 0; k < p.num_points(); k += 97) {
      double s = 0;
      for (int64_t o = p.point_offsets[k]; o < p.point_offsets[k + 1]; ++o) s += e[o];
      EXPECT_NEAR(m.points3D[cp.point_index[k]].error,
                  s / static_cast<double>(p.point_offsets[k + 1] - p.point_offsets[k]), 1e-12);
    }
  }
}

TEST(ColmapProblemTest, DroppedObservationsAndPointsLeaveTheModel) {
  ColmapModel model = SmallModel();
  const ColmapProblem cp = ProblemFromColmap(model, {}, "small");
  // Problem points: 100 (track (3,0) (5,1) (9,0)), 101 ((3,2) (5,0)); 102
  // has a track of 1 and is not in the problem.
  ASSERT_EQ(cp.problem.num_points(), 2);
  ASSERT_EQ(cp.problem.num_observations(), 5);
  UpdateColmapModel(cp, cp.problem, &model);
  // Drop 100's second observation and point 101 with both of its.
  RemoveDroppedObservations(cp, cp.problem, {1, 0, 1, 0, 0}, {1, 0}, &model);
  ASSERT_EQ(model.points3D.size(), 2u);
  EXPECT_EQ(model.points3D[0].point3D_id, 100);
  EXPECT_EQ(model.points3D[0].track,
            (std::vector<ColmapTrackElement>{{3, 0}, {9, 0}}));
  EXPECT_EQ(model.points3D[1].point3D_id, 102);  // untouched
  EXPECT_EQ(model.points3D[1].track, (std::vector<ColmapTrackElement>{{11, 0}}));
  auto image = [&](uint32_t id) -> const ColmapImage& {
    for (const ColmapImage& im : model.images) {
      if (im.image_id == id) return im;
    }
    throw std::logic_error("no image");
  };
  EXPECT_EQ(image(3).points2D[0].point3D_id, 100);
  EXPECT_EQ(image(3).points2D[2].point3D_id, kColmapNoPoint3D);  // was 101
  EXPECT_EQ(image(5).points2D[0].point3D_id, kColmapNoPoint3D);  // was 101
  EXPECT_EQ(image(5).points2D[1].point3D_id, kColmapNoPoint3D);  // the dropped observation
  EXPECT_EQ(image(9).points2D[0].point3D_id, 100);
  EXPECT_NO_THROW(ValidateColmapModel(model, "after", ".txt"));
  EXPECT_THROW(RemoveDroppedObservations(cp, cp.problem, {1, 1}, {1, 1}, &model),
               std::invalid_argument);
}

TEST(ColmapProblemTest, ObservationsAreTheTracksOfKeptPoints) {
  for (const char* folder : kModels) {
    SCOPED_TRACE(folder);
    const ColmapModel model = ReadColmapModel(SharedDir(folder));
    std::unordered_map<uint32_t, int64_t> image_of_id;
    for (size_t j = 0; j < model.images.size(); ++j) image_of_id[model.images[j].image_id] = j;
    for (int min_track : {1, 2, 3, 5}) {
      SCOPED_TRACE(min_track);
      ColmapProblemOptions options;
      options.min_track_length = min_track;
      const ColmapProblem cp = ProblemFromColmap(model, options, "m");
      const Problem& p = cp.problem;
      int64_t kept = 0, observations = 0;
      std::set<int64_t> observing;
      for (const ColmapPoint3D& q : model.points3D) {
        if (static_cast<int>(q.track.size()) < min_track) continue;
        ++kept;
        observations += static_cast<int64_t>(q.track.size());
        for (const ColmapTrackElement& t : q.track) observing.insert(image_of_id[t.image_id]);
      }
      ASSERT_EQ(p.num_points(), kept);
      ASSERT_EQ(p.num_observations(), observations);
      ASSERT_EQ(static_cast<int64_t>(p.point_offsets.size()), kept + 1);
      EXPECT_EQ(p.point_offsets.back(), observations);
      EXPECT_EQ(std::set<int64_t>(cp.image_index.begin(), cp.image_index.end()), observing);
      // Images in image-id order (the first, the lowest id, holds the gauge).
      EXPECT_TRUE(std::is_sorted(cp.image_index.begin(), cp.image_index.end(),
                                 [&](int64_t a, int64_t b) {
                                   return model.images[a].image_id < model.images[b].image_id;
                                 }));
      EXPECT_TRUE(std::is_sorted(cp.point_index.begin(), cp.point_index.end()));
      // Each observation is its track element's 2D point, seen by its image.
      for (int64_t k = 0; k < p.num_points(); ++k) {
        const ColmapPoint3D& q = model.points3D[cp.point_index[k]];
        ASSERT_EQ(p.point_offsets[k + 1] - p.point_offsets[k], static_cast<int64_t>(q.track.size()));
        for (size_t t = 0; t < q.track.size(); ++t) {
          const int64_t o = p.point_offsets[k] + static_cast<int64_t>(t);
          const int64_t j = image_of_id[q.track[t].image_id];
          ASSERT_EQ(cp.image_index[p.obs_camera[o]], j);
          const ColmapPoint2D& xy = model.images[j].points2D[q.track[t].point2D_idx];
          ASSERT_EQ(p.pixel(o)[0], xy.x);
          ASSERT_EQ(p.pixel(o)[1], xy.y);
        }
      }
    }
  }
}

TEST(ColmapProblemTest, SharedAndPerImageGroups) {
  struct Case {
    const char* folder;
    int64_t images, shared_groups;
  };
  // softmurata_177img has 690 camera entries, one per image used.
  const Case cases[] = {{"statue_of_liberty", 40, 1},
                        {"statue_of_liberty_small_txt", 40, 1},
                        {"fountain_p11", 11, 11},
                        {"softmurata_177img", 177, 177},
                        {"mithunnallana_6img", 6, 1}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.folder);
    const ColmapModel model = ReadColmapModel(SharedDir(c.folder));
    ColmapProblemOptions options;
    const ColmapProblem shared = ProblemFromColmap(model, options, "m");
    options.shared_intrinsics = false;
    ColmapProblem per_image = ProblemFromColmap(model, options, "m");
    ApplyFixings(ColmapFixings(model, per_image, {}, {}, {{-1, {"cx", "cy"}}}, "m"),
                 &per_image.problem);
    EXPECT_EQ(shared.problem.num_images(), c.images);
    EXPECT_EQ(shared.problem.num_groups(), c.shared_groups);
    EXPECT_EQ(per_image.problem.num_images(), c.images);
    EXPECT_EQ(per_image.problem.num_groups(), c.images);
    // SIMPLE_RADIAL's 4 parameters (f, cx, cy, k) per group, all free; then
    // cx, cy fixed.
    EXPECT_EQ(shared.problem.intrinsics_size, 4);
    EXPECT_EQ(static_cast<int64_t>(shared.problem.cameras.size()),
              6 * c.images + 4 * c.shared_groups);
    EXPECT_EQ(shared.problem.group_models,
              std::vector<LensModel>(c.shared_groups, LensModel::kSimpleRadial));
    EXPECT_TRUE(shared.problem.fixed_intrinsics.empty());
    for (uint16_t mask : per_image.problem.fixed_intrinsics) {
      EXPECT_EQ(mask, kIntrinsicCx | kIntrinsicCy);
    }
    EXPECT_TRUE(shared.problem.fixed_cameras.empty());
    for (int64_t i = 0; i < c.images; ++i) {
      EXPECT_EQ(per_image.problem.camera_intrinsics[i], i);
      // Each group holds its camera's parameters, k2 = 0.
      const ColmapImage& im = model.images[shared.image_index[i]];
      const int32_t g = shared.problem.camera_intrinsics[i];
      const ColmapCamera& cam = model.cameras[shared.group_camera[g]];
      ASSERT_EQ(cam.camera_id, im.camera_id);
      const double* x = shared.problem.intrinsics(g);
      EXPECT_EQ(std::vector<double>(x, x + 4), cam.params);
      const double* y = per_image.problem.intrinsics(i);
      EXPECT_EQ(std::vector<double>(y, y + 4), std::vector<double>(x, x + 4));
    }
  }
}

TEST(ColmapProblemTest, EveryModelKeepsItsParametersAndSizesTheGroups) {
  ColmapModel m = SmallModel();
  m.cameras[0].model_id = static_cast<int32_t>(LensModel::kPinhole);
  m.cameras[0].params = {500, 510, 320, 240};  // fx != fy is solved as such
  m.cameras[1].model_id = static_cast<int32_t>(LensModel::kOpenCV);
  m.cameras[1].params = {600, 601, 400, 300, 0.01, 0.02, 0.001, 0.002};
  ValidateColmapModel(m, "small", ".txt");
  const ColmapProblem cp = ProblemFromColmap(m, {}, "small");
  ASSERT_EQ(cp.group_camera, (std::vector<int64_t>{0, 1}));
  EXPECT_EQ(cp.problem.group_models,
            (std::vector<LensModel>{LensModel::kPinhole, LensModel::kOpenCV}));
  EXPECT_EQ(cp.problem.intrinsics_size, 8);
  EXPECT_TRUE(cp.problem.fixed_intrinsics.empty());
  EXPECT_EQ(cp.problem.intrinsics_free_mask(0), 0xF);
  EXPECT_EQ(cp.problem.intrinsics_free_mask(1), 0xFF);
  EXPECT_EQ(std::vector<double>(cp.problem.intrinsics(0), cp.problem.intrinsics(0) + 8),
            (std::vector<double>{500, 510, 320, 240, 0, 0, 0, 0}));
  EXPECT_EQ(std::vector<double>(cp.problem.intrinsics(1), cp.problem.intrinsics(1) + 8),
            m.cameras[1].params);
  // Written back, each camera keeps its model and gets its group's values.
  Problem adjusted = cp.problem;
  adjusted.intrinsics(0)[1] = 512;
  adjusted.intrinsics(1)[7] = 0.003;
  ColmapModel out = m;
  UpdateColmapModel(cp, adjusted, &out);
  const auto camera_of_image = [&](uint32_t image_id) {
    for (const ColmapImage& im : out.images) {
      if (im.image_id != image_id) continue;
      for (const ColmapCamera& c : out.cameras) {
        if (c.camera_id == im.camera_id) return c;
      }
    }
    return ColmapCamera{};
  };
  EXPECT_EQ(camera_of_image(3).model_id, static_cast<int32_t>(LensModel::kPinhole));
  EXPECT_EQ(camera_of_image(3).params, (std::vector<double>{500, 512, 320, 240}));
  EXPECT_EQ(camera_of_image(9).model_id, static_cast<int32_t>(LensModel::kOpenCV));
  EXPECT_EQ(camera_of_image(9).params,
            (std::vector<double>{600, 601, 400, 300, 0.01, 0.02, 0.001, 0.003}));
}

TEST(ColmapProblemTest, FixingsByNameFollowEachGroupsModel) {
  ColmapModel m = SmallModel();
  m.cameras[0].model_id = static_cast<int32_t>(LensModel::kSimpleRadial);
  m.cameras[0].params = {500, 320, 240, 0.01};
  m.cameras[1].model_id = static_cast<int32_t>(LensModel::kOpenCV);
  m.cameras[1].params = {600, 601, 400, 300, 0.01, 0.02, 0.001, 0.002};
  ColmapProblem cp = ProblemFromColmap(m, {}, "small");
  // k2 only in OPENCV's group; cx in both; fx in camera 2 only.
  ApplyFixings(ColmapFixings(m, cp, {}, {}, {{-1, {"k2", "cx"}}, {2, {"fx"}}}, "small"),
               &cp.problem);
  EXPECT_EQ(cp.problem.fixed_intrinsics, (std::vector<uint16_t>{0x2, 0x1 | 0x4 | 0x20}));
  // A name no model has, with the models' names; an unknown camera id.
  ColmapProblem again = ProblemFromColmap(m, {}, "small");
  try {
    ApplyFixings(ColmapFixings(m, again, {}, {}, {{-1, {"k3"}}}, "small"), &again.problem);
    ADD_FAILURE() << "k3 accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'k3'"), std::string::npos) << what;
    EXPECT_NE(what.find("SIMPLE_RADIAL (f, cx, cy, k)"), std::string::npos) << what;
    EXPECT_NE(what.find("OPENCV (fx, fy, cx, cy, k1, k2, p1, p2)"), std::string::npos) << what;
  }
  EXPECT_TRUE(again.problem.fixed_intrinsics.empty());  // nothing half-applied
  try {
    ApplyFixings(ColmapFixings(m, again, {}, {}, {{7, {"k2"}}}, "small"), &again.problem);
    ADD_FAILURE() << "k2 accepted in camera 7 (SIMPLE_RADIAL)";
  } catch (const UsageError& e) {  // named by the camera's id, not a group's index
    EXPECT_NE(std::string(e.what()).find("'k2' in COLMAP camera 7's model SIMPLE_RADIAL"),
              std::string::npos)
        << e.what();
  }
  try {
    ColmapFixings(m, again, {}, {}, {{77, {"f"}}}, "/the/model");
    ADD_FAILURE() << "camera 77 accepted";
  } catch (const UsageError& e) {
    EXPECT_EQ(std::string(e.what()),
              "--fix-intrinsics: camera 77: /the/model has no camera with that id");
  }
}

TEST(ColmapProblemTest, FixedImagesAndBadOptions) {
  const ColmapModel model = ReadColmapModel(SharedDir("statue_of_liberty"));
  ColmapProblemOptions options;
  const std::set<uint32_t> fixed = {model.images[0].image_id, model.images[17].image_id};
  std::vector<uint32_t> fixed_ids(fixed.begin(), fixed.end());
  ColmapProblem cp = ProblemFromColmap(model, options, "m");
  EXPECT_TRUE(cp.problem.fixed_cameras.empty());
  ApplyFixings(ColmapFixings(model, cp, fixed_ids, {}, {}, "m"), &cp.problem);
  ASSERT_EQ(cp.problem.fixed_cameras.size(), 40u);
  int count = 0;
  for (int64_t i = 0; i < 40; ++i) {
    const bool want = fixed.count(model.images[cp.image_index[i]].image_id) > 0;
    EXPECT_EQ(cp.problem.camera_fixed(i), want) << i;
    count += cp.problem.camera_fixed(i);
  }
  EXPECT_EQ(count, 2);

  uint32_t unknown = 0;
  for (const ColmapImage& im : model.images) unknown = std::max(unknown, im.image_id);
  unknown += 1000;
  fixed_ids.push_back(unknown);
  try {
    ColmapFixings(model, cp, fixed_ids, {}, {}, "/the/model");
    ADD_FAILURE() << "an unknown image id was taken";
  } catch (const UsageError& e) {  // exit 2: the flag's value, not the model
    EXPECT_EQ(std::string(e.what()), "--fix-images: image " + std::to_string(unknown) +
                                         ": /the/model has no image with that id");
  }
  fixed_ids.pop_back();
  // A camera's names checked against its own model, named by its id.
  const uint32_t camera = model.cameras[0].camera_id;
  try {
    ColmapFixings(model, cp, fixed_ids, {}, {{camera, {"f", "zz"}}}, "/the/model");
    ADD_FAILURE() << "an unknown parameter name was taken";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("--fix-intrinsics: no intrinsic parameter 'zz' in COLMAP camera " +
                                         std::to_string(camera) + "'s model"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(ColmapFixings(model, cp, fixed_ids, {}, {{unknown, {"f"}}}, "/the/model"), UsageError);

  ColmapProblemOptions bad;
  bad.min_track_length = 0;
  EXPECT_THROW(ProblemFromColmap(model, bad, "m"), std::invalid_argument);
}

TEST(ColmapProblemTest, PerImageWriteBackCreatesNewCameras) {
  const std::string dir = SharedDir("statue_of_liberty");
  const ColmapModel model = ReadColmapModel(dir);
  ASSERT_EQ(model.cameras.size(), 1u);
  const uint32_t id0 = model.cameras[0].camera_id;
  ColmapProblemOptions options;
  options.shared_intrinsics = false;
  const ColmapProblem cp = ProblemFromColmap(model, options, dir);
  ASSERT_EQ(cp.problem.num_groups(), 40);
  Problem adjusted = cp.problem;
  for (int64_t g = 0; g < 40; ++g) {
    double* x = adjusted.intrinsics(g);
    x[0] *= 1.0 + 0.001 * static_cast<double>(g);
    x[1] += 0.5 * static_cast<double>(g);
    x[3] = -0.01 * static_cast<double>(g);
  }
  ColmapModel m = model;
  UpdateColmapModel(cp, adjusted, &m);
  ASSERT_EQ(m.cameras.size(), 40u);
  // The first image keeps the camera; the others get ids id0 + 1, + 2, ...
  EXPECT_EQ(m.images[0].camera_id, id0);
  EXPECT_EQ(m.cameras[0].camera_id, id0);
  for (size_t j = 1; j < 40; ++j) {
    EXPECT_EQ(m.images[j].camera_id, id0 + j);
    EXPECT_EQ(m.cameras[j].camera_id, id0 + j);
    EXPECT_EQ(m.cameras[j].model_id, model.cameras[0].model_id);
    EXPECT_EQ(m.cameras[j].width, model.cameras[0].width);
    EXPECT_EQ(m.cameras[j].height, model.cameras[0].height);
  }
  // Through a file: every image's intrinsics are its group's.
  const std::string out = dba::testing::FreshTempDir("per_image");
  WriteColmapBinary(m, out);
  const ColmapModel back = ReadColmapModel(out);
  EXPECT_EQ(FirstColmapModelDifference(m, back), "");
  std::unordered_map<uint32_t, const ColmapCamera*> cams;
  for (const ColmapCamera& c : back.cameras) cams[c.camera_id] = &c;
  for (int64_t i = 0; i < 40; ++i) {
    const ColmapImage& im = back.images[cp.image_index[i]];
    const double* x = adjusted.intrinsics(adjusted.camera_intrinsics[i]);
    EXPECT_EQ(cams.at(im.camera_id)->params, std::vector<double>(x, x + 4));
  }
  // And a problem built from the written model, shared, has 40 groups equal
  // to the adjusted ones.
  const ColmapProblem again = ProblemFromColmap(back, {}, out);
  ASSERT_EQ(again.problem.num_groups(), 40);
  for (int64_t i = 0; i < 40; ++i) {
    const double* a = again.problem.intrinsics(again.problem.camera_intrinsics[i]);
    const double* b = adjusted.intrinsics(i);
    EXPECT_EQ(std::vector<double>(a, a + 4), std::vector<double>(b, b + 4));
  }
}

TEST(ColmapProblemTest, ChangedParametersAreWrittenBack) {
  const ColmapModel model = SmallModel();
  const ColmapProblem cp = ProblemFromColmap(model, {}, "small");
  // Image d (index 0, camera 7's first user) sees only the one-view point 102.
  EXPECT_EQ(cp.image_index, (std::vector<int64_t>{1, 2, 3}));
  EXPECT_EQ(cp.point_index, (std::vector<int64_t>{0, 2}));
  EXPECT_EQ(cp.group_camera, (std::vector<int64_t>{0, 1}));
  EXPECT_EQ(cp.problem.camera_intrinsics, (std::vector<int32_t>{0, 0, 1}));
  // b's quaternion (-1, 0, 0, 0) is the identity.
  for (int d = 0; d < 3; ++d) EXPECT_EQ(cp.problem.camera(1)[d], 0.0);

  Problem adjusted = cp.problem;
  // A rotation of 3 rad about (2, -1, 2)/3 for image a; its quaternion has qw > 0.
  const Vec3 omega = Vec3(2, -1, 2);
  for (int d = 0; d < 3; ++d) adjusted.camera(0)[d] = omega[d];
  // 4 rad (> π) for image c: written with qw >= 0 as the same rotation.
  const Vec3 omega_c = Vec3(0, 0, 4);
  for (int d = 0; d < 3; ++d) adjusted.camera(2)[d] = omega_c[d];
  adjusted.camera(2)[5] = 2.5;
  adjusted.intrinsics(0)[0] = 510;
  adjusted.intrinsics(1)[3] = 0.07;
  adjusted.point(1)[2] = 5.5;

  ColmapModel m = model;
  UpdateColmapModel(cp, adjusted, &m);
  auto rotation = [](const std::array<double, 4>& q) {
    return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
  };
  EXPECT_NEAR(std::hypot(std::hypot(m.images[1].qvec[0], m.images[1].qvec[1]),
                         std::hypot(m.images[1].qvec[2], m.images[1].qvec[3])),
              1.0, 1e-15);
  EXPECT_GT(m.images[1].qvec[0], 0.0);
  EXPECT_LT((rotation(m.images[1].qvec) - AngleAxisToRotation(omega)).norm(), 1e-14);
  EXPECT_GE(m.images[3].qvec[0], 0.0);
  EXPECT_NEAR(m.images[3].qvec[0], std::abs(std::cos(2.0)), 1e-15);
  EXPECT_LT((rotation(m.images[3].qvec) - AngleAxisToRotation(omega_c)).norm(), 1e-14);
  EXPECT_EQ(m.images[3].tvec[2], 2.5);
  EXPECT_EQ(m.images[2].qvec, (std::array<double, 4>{1, 0, 0, 0}));

  // Camera 7's first user (d) is not in the problem: camera 7 stays as it
  // was, for d, and a and b move to a new camera 8 holding their group.
  ASSERT_EQ(m.cameras.size(), 3u);
  EXPECT_EQ(m.cameras[0], model.cameras[0]);
  EXPECT_EQ(m.images[0], model.images[0]);
  EXPECT_EQ(m.cameras[2].camera_id, 8u);
  EXPECT_EQ(m.cameras[2].params, (std::vector<double>{510, 320, 240, -0.1}));
  EXPECT_EQ(m.images[1].camera_id, 8u);
  EXPECT_EQ(m.images[2].camera_id, 8u);
  // Camera 2's first user (c) is in the problem: written in place.
  EXPECT_EQ(m.cameras[1].camera_id, 2u);
  EXPECT_EQ(m.cameras[1].params, (std::vector<double>{600, 400, 300, 0.07}));
  EXPECT_EQ(m.images[3].camera_id, 2u);

  // Points: the moved one and the errors at the new parameters; the one-view
  // point is unchanged.
  EXPECT_EQ(m.points3D[2].xyz, (std::array<double, 3>{1, 0, 5.5}));
  EXPECT_EQ(m.points3D[1], model.points3D[1]);
  const std::vector<double> e = ObservationErrors(adjusted);
  EXPECT_NEAR(m.points3D[0].error, (e[0] + e[1] + e[2]) / 3, 1e-12);
  EXPECT_NEAR(m.points3D[2].error, (e[3] + e[4]) / 2, 1e-12);
  EXPECT_GT(m.points3D[2].error, 1.0);

  // With min_track_length 1 every image is in the problem and camera 7 is
  // written in place.
  ColmapProblemOptions all;
  all.min_track_length = 1;
  const ColmapProblem cp1 = ProblemFromColmap(model, all, "small");
  EXPECT_EQ(cp1.problem.num_images(), 4);
  Problem adjusted1 = cp1.problem;
  adjusted1.intrinsics(0)[0] = 505;
  ColmapModel m1 = model;
  UpdateColmapModel(cp1, adjusted1, &m1);
  ASSERT_EQ(m1.cameras.size(), 2u);
  EXPECT_EQ(m1.cameras[0].params[0], 505.0);

  // A mismatched adjusted problem is refused.
  Problem wrong = cp.problem;
  wrong.points.push_back(0);
  EXPECT_THROW(UpdateColmapModel(cp, wrong, &m), std::invalid_argument);
  wrong = cp.problem;
  wrong.obs_camera[0] = 1;
  EXPECT_THROW(UpdateColmapModel(cp, wrong, &m), std::invalid_argument);
}

}  // namespace
}  // namespace dba
