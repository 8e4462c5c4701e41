#include "dba/common/shared_library.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace dba {
namespace {

std::string ErrorOf(void (*f)()) {
  try {
    f();
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(SharedLibrary, ResolvesAFunctionByName) {
  const SharedLibrary m("libm.so.6", "a test");
  const auto fabs = m.Symbol<double (*)(double)>("fabs");
  EXPECT_EQ(fabs(-2.5), 2.5);
}

TEST(SharedLibrary, AMissingLibraryIsNamedWithWhatNeedsIt) {
  const std::string e = ErrorOf([] { SharedLibrary("libdba-no-such-library.so.7", "georeferencing"); });
  EXPECT_NE(e.find("georeferencing needs the shared library libdba-no-such-library.so.7"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("did not load: "), std::string::npos) << e;
}

TEST(SharedLibrary, AMissingSymbolIsNamed) {
  const std::string e =
      ErrorOf([] { SharedLibrary("libm.so.6", "a test").Symbol<void (*)()>("dba_no_such_symbol"); });
  EXPECT_NE(e.find("libm.so.6 has no symbol dba_no_such_symbol"), std::string::npos) << e;
}

}  // namespace
}  // namespace dba
