// Writing by file extension; see read_problem.h.
#include "dba/io/read_problem.h"

#include <filesystem>
#include <new>
#include <stdexcept>

#include "dba/io/path_kind.h"
#include "dba/common/error.h"
#include "dba/io/bal_writer.h"
#include "dba/io/colmap_model.h"

namespace dba {

Problem ReadProblem(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    if (DetectColmapFormat(path).has_value()) {
      throw InputError(path, 0,
                       "is a COLMAP model directory: dba solve reads it directly, and dba "
                       "convert makes a .dba of it; this command reads BAL text (.txt, .bz2) "
                       "and dba binary (.dba) problems");
    }
    throw InputError(path, 0, "is a directory; expected a BAL (.txt, .bz2) or .dba problem file");
  }
  if (!IsBinaryProblem(path) && KindOfPath(path) == PathKind::kBinary) {
    // Not read as BAL text: a .dba whose magic is damaged would fail there
    // with a misleading message.
    throw InputError(path, 0, "does not start with the dba binary magic (corrupt or not a .dba "
                              "file); BAL text files end in .txt or .bz2");
  }
  try {
    return IsBinaryProblem(path) ? ReadBinaryProblem(path) : ReadBal(path);
  } catch (const std::bad_alloc&) {
    throw InputError(path, 0, "out of memory reading the problem (its counts need more memory "
                              "than this machine has)");
  } catch (const std::length_error& e) {
    throw InputError(path, 0, std::string("counts too large to hold in memory (") + e.what() + ")");
  }
}

void WriteProblem(const Problem& problem, const std::string& path) {
  if (KindOfPath(path) == PathKind::kBinary) {
    WriteBinaryProblem(problem, path);
  } else {
    WriteBal(problem, path);
  }
}

}  // namespace dba
