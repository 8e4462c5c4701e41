// Tests that read ../shared/data (the BAL and COLMAP problems beside the
// repository) fail, when it is missing, with the reader's error naming the
// file; this environment says once, before any test, what is missing and
// where it was looked for.
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>

namespace dba::testing {
namespace {

class SharedData : public ::testing::Environment {
 public:
  void SetUp() override {
    for (const char* dir : {"bal", "colmap"}) {
      const std::filesystem::path path = std::filesystem::path(DBA_SHARED_DATA_DIR) / dir;
      if (!std::filesystem::is_directory(path)) {
        std::cerr << "dba tests: missing " << path.string()
                  << " (the shared data, ../shared/data beside the repository): the tests "
                     "that read it will fail naming the files they could not open\n";
      }
    }
  }
};

[[maybe_unused]] ::testing::Environment* const kSharedData =
    ::testing::AddGlobalTestEnvironment(new SharedData);

}  // namespace
}  // namespace dba::testing
