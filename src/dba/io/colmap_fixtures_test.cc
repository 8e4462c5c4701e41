// COLMAP round trips for every camera model, on the checked-in fixtures
// (tests/data/colmap_models/<MODEL>/{text,binary}, made by
// scripts/make_colmap_fixtures.py: two cameras of the model, four images,
// twelve points): read and written without solving, binary is byte-identical
// and text keeps every value and is idempotent; read as a problem and
// written back unchanged, each camera keeps its model and its params bit for
// bit.
#include <gtest/gtest.h>

#include <string>

#include "dba/io/colmap_binary.h"
#include "dba/io/colmap_model.h"
#include "dba/io/colmap_problem.h"
#include "dba/io/colmap_text.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

std::string Fixture(const std::string& model, const char* form) {
  return std::string(DBA_TEST_DATA_DIR) + "/colmap_models/" + model + "/" + form;
}

TEST(ColmapFixtures, EveryModelRoundTripsInBothForms) {
  for (const ColmapCameraModelInfo& info : ColmapCameraModels()) {
    const std::string name = info.name;
    SCOPED_TRACE(name);
    const ColmapModel binary = ReadColmapModel(Fixture(name, "binary"));
    const ColmapModel text = ReadColmapModel(Fixture(name, "text"));
    ASSERT_EQ(binary.cameras.size(), 2u);
    for (const ColmapCamera& c : binary.cameras) EXPECT_EQ(c.ModelName(), name);
    EXPECT_EQ(FirstColmapModelDifference(binary, text), "");

    const std::string out = testing::FreshTempDir("fixture_" + name);
    WriteColmapBinary(binary, out + "/bin");
    for (const char* file : {"cameras.bin", "images.bin", "points3D.bin"}) {
      EXPECT_EQ(testing::ReadFileBytes(out + "/bin/" + file),
                testing::ReadFileBytes(Fixture(name, "binary") + "/" + file))
          << file << " is not byte-identical";
    }
    WriteColmapText(text, out + "/text1");
    const ColmapModel again = ReadColmapModel(out + "/text1");
    EXPECT_EQ(FirstColmapModelDifference(again, text), "");
    WriteColmapText(again, out + "/text2");
    for (const char* file : {"cameras.txt", "images.txt", "points3D.txt"}) {
      EXPECT_EQ(testing::ReadFileBytes(out + "/text1/" + file),
                testing::ReadFileBytes(out + "/text2/" + file))
          << file << " changed when written again";
    }
  }
}

TEST(ColmapFixtures, EveryModelIsAProblemOfThatModelAndWritesBackUnchanged) {
  for (const ColmapCameraModelInfo& info : ColmapCameraModels()) {
    SCOPED_TRACE(info.name);
    const ColmapModel model = ReadColmapModel(Fixture(info.name, "binary"));
    const ColmapProblem cp = ProblemFromColmap(model, {}, Fixture(info.name, "binary"));
    ASSERT_EQ(cp.problem.num_groups(), 2);
    EXPECT_EQ(cp.problem.group_models, std::vector<LensModel>(2, info.id));
    EXPECT_EQ(cp.problem.intrinsics_size, info.num_params);
    ColmapModel written = model;
    UpdateColmapModel(cp, cp.problem, &written);
    ASSERT_EQ(written.cameras.size(), model.cameras.size());
    for (size_t c = 0; c < model.cameras.size(); ++c) {
      EXPECT_EQ(written.cameras[c].model_id, model.cameras[c].model_id);
      EXPECT_EQ(written.cameras[c].params, model.cameras[c].params);
    }
  }
}

}  // namespace
}  // namespace dba
