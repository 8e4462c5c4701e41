// libFuzzer target: a COLMAP binary model, the input cut at the bytes
// "\n--\n" into cameras.bin, images.bin and points3D.bin (binary files hold
// NULs everywhere).
#include <exception>
#include <string_view>

#include "dba/io/colmap_binary.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& dir = dba::fuzz::Dir();
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  std::string_view parts[3];
  for (int p = 0; p < 3; ++p) {
    const size_t at = p < 2 ? rest.find("\n--\n") : std::string_view::npos;
    parts[p] = rest.substr(0, at);
    rest = at == std::string_view::npos ? std::string_view() : rest.substr(at + 4);
  }
  dba::fuzz::WriteFile(dir + "/cameras.bin", parts[0]);
  dba::fuzz::WriteFile(dir + "/images.bin", parts[1]);
  dba::fuzz::WriteFile(dir + "/points3D.bin", parts[2]);
  try {
    dba::ReadColmapBinary(dir);
  } catch (const std::exception&) {
  }
  return 0;
}
