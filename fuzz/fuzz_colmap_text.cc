// libFuzzer target: a COLMAP text model, the input cut at NUL bytes into
// cameras.txt, images.txt and points3D.txt.
#include <exception>

#include "dba/io/colmap_text.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& dir = dba::fuzz::Dir();
  const auto parts = dba::fuzz::Split(data, size, 3);
  dba::fuzz::WriteFile(dir + "/cameras.txt", parts[0]);
  dba::fuzz::WriteFile(dir + "/images.txt", parts[1]);
  dba::fuzz::WriteFile(dir + "/points3D.txt", parts[2]);
  try {
    dba::ReadColmapText(dir);
  } catch (const std::exception&) {
  }
  return 0;
}
