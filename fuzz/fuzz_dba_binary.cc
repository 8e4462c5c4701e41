// libFuzzer target: a dba binary problem (.dba) through ReadProblem.
#include <exception>

#include "dba/io/read_problem.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = dba::fuzz::Dir() + "/problem.dba";
  dba::fuzz::WriteFile(path, {reinterpret_cast<const char*>(data), size});
  try {
    dba::ReadProblem(path);
  } catch (const std::exception&) {
  }
  return 0;
}
