// Writing by file extension; see read_problem.h.
#include "dba/io/read_problem.h"

#include <filesystem>

#include "dba/common/error.h"
#include "dba/io/bal_writer.h"
#include "dba/io/colmap_model.h"

namespace dba {

BalProblem ReadProblem(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    if (DetectColmapFormat(path).has_value()) {
      throw InputError(path, 0,
                       "is a COLMAP model directory: dba solve reads it directly; this "
                       "command reads BAL text (.txt, .bz2) and dba binary (.dba) problems");
    }
    throw InputError(path, 0, "is a directory; expected a BAL (.txt, .bz2) or .dba problem file");
  }
  return IsBinaryProblem(path) ? ReadBinaryProblem(path) : ReadBal(path);
}

void WriteProblem(const BalProblem& problem, const std::string& path) {
  if (path.size() >= 4 && path.compare(path.size() - 4, 4, ".dba") == 0) {
    WriteBinaryProblem(problem, path);
  } else {
    WriteBal(problem, path);
  }
}

}  // namespace dba
