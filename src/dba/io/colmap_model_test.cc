// Tests of the COLMAP model layer: the camera model table, ReadColmapModel's
// format detection on every shared model (counts as in data/README.md §3,
// every track pointing back), validation errors, and the mapping of COLMAP
// cameras onto the photogrammetric intrinsics (f, cx, cy, k1, k2).
#include "dba/testing/temp_files.h"
#include "dba/io/colmap_model.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "dba/common/error.h"
#include "dba/io/colmap_binary.h"
#include "dba/io/colmap_text.h"

namespace dba {
namespace {

namespace fs = std::filesystem;

struct SharedModel {
  const char* folder;
  ColmapFormat format;
  size_t cameras, images, points3D;
  int64_t observations;
};

// data/README.md §3.
const SharedModel kShared[] = {
    {"statue_of_liberty", ColmapFormat::kBinary, 1, 40, 9066, 37739},
    {"statue_of_liberty_small_txt", ColmapFormat::kText, 1, 40, 1816, 7760},
    {"fountain_p11", ColmapFormat::kBinary, 11, 11, 14073, 68862},
    {"softmurata_177img", ColmapFormat::kBinary, 690, 177, 4217, 129186},
    {"mithunnallana_6img", ColmapFormat::kText, 1, 6, 2028, 5868},
};

std::string SharedDir(const char* folder) {
  return std::string(DBA_SHARED_DATA_DIR) + "/colmap/" + folder + "/sparse/0";
}

// A fresh directory, private to this process and removed when it exits.
std::string TempDir(const std::string& name) {
  return dba::testing::FreshTempDir(name);
}

// Runs `f`, expecting an InputError whose message contains every one of
// `phrases`; returns the message.
template <typename F>
std::string ExpectInputError(F f, const std::vector<std::string>& phrases) {
  try {
    f();
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const std::string& p : phrases) {
      EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
    }
    return msg;
  }
  ADD_FAILURE() << "no InputError";
  return "";
}

// A small valid model: two SIMPLE_RADIAL images sharing a camera, two points.
ColmapModel TinyModel() {
  ColmapModel m;
  m.cameras.push_back({7, 2, 640, 480, {500, 320, 240, -0.1}});
  ColmapImage a;
  a.image_id = 3;
  a.camera_id = 7;
  a.name = "a.jpg";
  a.points2D = {{10, 20, 100}, {30, 40, kColmapNoPoint3D}, {50, 60, 101}};
  ColmapImage b = a;
  b.image_id = 5;
  b.name = "b.jpg";
  b.tvec = {1, 0, 0};
  b.points2D = {{11, 21, 101}, {31, 41, 100}};
  m.images = {a, b};
  m.points3D.push_back({100, {0, 0, 5}, {255, 0, 0}, 0.5, {{3, 0}, {5, 1}}});
  m.points3D.push_back({101, {1, 0, 5}, {0, 255, 0}, 0.25, {{3, 2}, {5, 0}}});
  return m;
}

TEST(ColmapModelTest, CameraModelTableMatchesColmap) {
  const auto models = ColmapCameraModels();
  ASSERT_EQ(models.size(), 18u);
  std::set<std::string> names;
  for (size_t i = 0; i < models.size(); ++i) {
    EXPECT_EQ(static_cast<int32_t>(models[i].id), static_cast<int32_t>(i));
    EXPECT_TRUE(names.insert(models[i].name).second) << models[i].name;
    EXPECT_EQ(FindColmapCameraModel(models[i].name), &models[i]);
    EXPECT_EQ(FindColmapCameraModel(static_cast<int32_t>(models[i].id)), &models[i]);
  }
  const std::pair<const char*, int> expected[] = {
      {"SIMPLE_PINHOLE", 3}, {"PINHOLE", 4},         {"SIMPLE_RADIAL", 4},
      {"RADIAL", 5},         {"OPENCV", 8},          {"OPENCV_FISHEYE", 8},
      {"FULL_OPENCV", 12},   {"FOV", 5},             {"SIMPLE_RADIAL_FISHEYE", 4},
      {"RADIAL_FISHEYE", 5}, {"THIN_PRISM_FISHEYE", 12}, {"RAD_TAN_THIN_PRISM_FISHEYE", 16},
      {"SIMPLE_DIVISION", 4}, {"DIVISION", 5},        {"SIMPLE_FISHEYE", 3},
      {"FISHEYE", 4},        {"EUCM", 6},            {"EQUIRECTANGULAR", 2}};
  for (const auto& [name, n] : expected) {
    ASSERT_NE(FindColmapCameraModel(name), nullptr) << name;
    EXPECT_EQ(FindColmapCameraModel(name)->num_params, n) << name;
  }
  EXPECT_EQ(FindColmapCameraModel("NOPE"), nullptr);
  EXPECT_EQ(FindColmapCameraModel(-1), nullptr);
  EXPECT_EQ(FindColmapCameraModel(18), nullptr);
  EXPECT_EQ(FindColmapCameraModel("BROWN"), nullptr);  // dba's own, not COLMAP's
  EXPECT_EQ(FindColmapCameraModel(static_cast<int32_t>(LensModel::kBrown)), nullptr);
  ColmapCamera c;
  c.model_id = 42;
  EXPECT_EQ(c.ModelName(), "UNKNOWN(42)");
}

TEST(ColmapModelTest, SharedModelsHaveTheReadmeCountsAndConsistentTracks) {
  for (const SharedModel& s : kShared) {
    SCOPED_TRACE(s.folder);
    const std::string dir = SharedDir(s.folder);
    ASSERT_EQ(DetectColmapFormat(dir), s.format);
    const ColmapModel m = ReadColmapModel(dir);
    EXPECT_EQ(m.cameras.size(), s.cameras);
    EXPECT_EQ(m.images.size(), s.images);
    EXPECT_EQ(m.points3D.size(), s.points3D);
    EXPECT_EQ(m.NumObservations(), s.observations);
    EXPECT_EQ(m.NumPoints2DWithPoint3D(), s.observations);

    // Every track element points back, independently of the reader's checks.
    std::unordered_map<uint32_t, const ColmapImage*> images;
    for (const ColmapImage& im : m.images) images[im.image_id] = &im;
    int64_t checked = 0;
    for (const ColmapPoint3D& p : m.points3D) {
      for (const ColmapTrackElement& e : p.track) {
        auto it = images.find(e.image_id);
        ASSERT_NE(it, images.end());
        ASSERT_LT(e.point2D_idx, it->second->points2D.size());
        ASSERT_EQ(it->second->points2D[e.point2D_idx].point3D_id, p.point3D_id);
        ++checked;
      }
    }
    EXPECT_EQ(checked, s.observations);

    // Every camera is SIMPLE_RADIAL.
    for (const ColmapCamera& c : m.cameras) {
      ASSERT_EQ(c.ModelName(), "SIMPLE_RADIAL");
      EXPECT_EQ(LensModelOfColmapCamera(c), LensModel::kSimpleRadial);
    }
  }
}

TEST(ColmapModelTest, ReadColmapModelExplainsMissingFiles) {
  const std::string base = std::string(DBA_SHARED_DATA_DIR) + "/colmap/fountain_p11";
  ExpectInputError([&] { ReadColmapModel(base); },
                   {"no complete COLMAP model", "found none of them", base + "/sparse/0"});
  ExpectInputError([&] { ReadColmapModel(base + "/nonexistent"); }, {"no such directory"});
  ExpectInputError([&] { ReadColmapModel(SharedDir("fountain_p11") + "/cameras.bin"); },
                   {"not a directory"});

  const std::string dir = TempDir("partial");
  WriteColmapText(TinyModel(), dir);
  fs::remove(dir + "/points3D.txt");
  EXPECT_EQ(DetectColmapFormat(dir), std::nullopt);
  ExpectInputError([&] { ReadColmapModel(dir); }, {"found cameras.txt, images.txt"});
}

TEST(ColmapModelTest, BinaryIsPreferredWhenBothFormsArePresent) {
  const std::string dir = TempDir("both");
  ColmapModel m = TinyModel();
  WriteColmapText(m, dir);
  EXPECT_EQ(DetectColmapFormat(dir), ColmapFormat::kText);
  m.points3D[0].error = 0.75;
  WriteColmapBinary(m, dir);
  EXPECT_EQ(DetectColmapFormat(dir), ColmapFormat::kBinary);
  EXPECT_EQ(ReadColmapModel(dir).points3D[0].error, 0.75);
  EXPECT_EQ(ReadColmapText(dir).points3D[0].error, 0.5);
}

TEST(ColmapModelTest, ValidationNamesTheInconsistency) {
  EXPECT_NO_THROW(ValidateColmapModel(TinyModel(), "d", ".bin"));
  struct Case {
    const char* name;
    void (*mutate)(ColmapModel*);
    std::vector<std::string> phrases;
  };
  const Case cases[] = {
      {"duplicate camera", [](ColmapModel* m) { m->cameras.push_back(m->cameras[0]); },
       {"d/cameras.bin", "camera #1 (id 7)", "appears twice"}},
      {"wrong param count", [](ColmapModel* m) { m->cameras[0].params.pop_back(); },
       {"SIMPLE_RADIAL has 4 parameters", "has 3"}},
      {"unknown model", [](ColmapModel* m) { m->cameras[0].model_id = 99; },
       {"unknown camera model id 99"}},
      {"missing camera", [](ColmapModel* m) { m->images[1].camera_id = 8; },
       {"d/images.bin", "image #1 (id 5)", "camera_id 8 is not in d/cameras.bin"}},
      {"duplicate image", [](ColmapModel* m) { m->images[1].image_id = 3; },
       {"image #1 (id 3)", "appears twice"}},
      {"nan pose", [](ColmapModel* m) { m->images[0].tvec[2] = std::nan(""); },
       {"non-finite qvec or tvec"}},
      {"inf 2D point", [](ColmapModel* m) { m->images[0].points2D[1].x = std::numeric_limits<double>::infinity(); },
       {"point2D 1: pixel (inf, ", "is not finite"}},
      {"2D point of 1e80", [](ColmapModel* m) { m->images[0].points2D[1].y = 1e80; },
       {"d/images.bin", "point2D 1: pixel (", ", 1e+80) is beyond 1e7 px from the origin: no image is that large"}},
      {"missing track image", [](ColmapModel* m) { m->points3D[0].track[0].image_id = 9; },
       {"d/points3D.bin", "point3D #0 (id 100)", "track element 0 (image 9", "no such image"}},
      {"idx out of range", [](ColmapModel* m) { m->points3D[0].track[1].point2D_idx = 2; },
       {"point2D_idx 2", "has only 2 2D points"}},
      {"no back reference", [](ColmapModel* m) { m->points3D[0].track[0].point2D_idx = 1; },
       {"refers to point3D_id -1, not back"}},
      {"duplicate track element",
       [](ColmapModel* m) {
         m->points3D[0].track.push_back(m->points3D[0].track[0]);
       },
       {"listed twice"}},
      {"2D point not in track",
       [](ColmapModel* m) { m->points3D[1].track.pop_back(); },
       {"d/images.bin", "image #1 (id 5)", "point2D 0 refers to point3D_id 101",
        "track does not list"}},
      {"2D point to missing 3D point",
       [](ColmapModel* m) { m->images[0].points2D[1].point3D_id = 555; },
       {"point2D 1 refers to point3D_id 555 which is not in d/points3D.bin"}},
      {"duplicate point", [](ColmapModel* m) { m->points3D[1].point3D_id = 100; },
       {"point3D #1 (id 100)", "appears twice"}},
      {"bad point3D ref", [](ColmapModel* m) { m->images[0].points2D[1].point3D_id = -2; },
       {"expected -1 or >= 0"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    ColmapModel m = TinyModel();
    c.mutate(&m);
    ExpectInputError([&] { ValidateColmapModel(m, "d", ".bin"); }, c.phrases);
  }
}

TEST(ColmapModelTest, FirstDifferenceFindsBitLevelChanges) {
  const ColmapModel a = TinyModel();
  EXPECT_EQ(FirstColmapModelDifference(a, a), "");
  ColmapModel b = a;
  b.images[1].points2D[1].y = std::nextafter(41.0, 42.0);
  EXPECT_NE(FirstColmapModelDifference(a, b).find("image #1 (id 5): point2D 1"),
            std::string::npos);
  b = a;
  b.points3D[1].xyz[0] = 0.0;
  ColmapModel c = b;
  c.points3D[1].xyz[0] = -0.0;
  EXPECT_NE(FirstColmapModelDifference(b, c).find("xyz[0]"), std::string::npos);
  EXPECT_EQ(b, c);  // operator== compares values, FirstColmapModelDifference bits
}

TEST(ColmapModelTest, EveryColmapModelIsALensModelWithItsParameters) {
  for (const ColmapCameraModelInfo& info : ColmapCameraModels()) {
    SCOPED_TRACE(info.name);
    ColmapCamera c;
    c.camera_id = 4;
    c.model_id = static_cast<int32_t>(info.id);
    c.params.assign(info.num_params, 1.0);
    EXPECT_EQ(LensModelOfColmapCamera(c), info.id);
    c.params.push_back(2.0);
    ExpectInputError([&] { LensModelOfColmapCamera(c, "x/cameras.txt"); },
                     {"x/cameras.txt", "camera 4", std::string(info.name) + " needs " +
                                                       std::to_string(info.num_params)});
  }
  ColmapCamera c;
  c.model_id = 40;
  ExpectInputError([&] { LensModelOfColmapCamera(c); }, {"unknown camera model id 40"});
}

}  // namespace
}  // namespace dba
