// libFuzzer target: a BAL text problem (dba's ReadProblem on a .txt file).
#include <exception>

#include "dba/io/read_problem.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = dba::fuzz::Dir() + "/problem.txt";
  dba::fuzz::WriteFile(path, {reinterpret_cast<const char*>(data), size});
  try {
    dba::ReadProblem(path);
  } catch (const std::exception&) {
    // Refused: fine. Crashes, hangs and unbounded allocation are not.
  }
  return 0;
}
