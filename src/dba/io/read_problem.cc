// Writing by file extension; see read_problem.h.
#include "dba/io/read_problem.h"

#include "dba/io/bal_writer.h"

namespace dba {

void WriteProblem(const BalProblem& problem, const std::string& path) {
  if (path.size() >= 4 && path.compare(path.size() - 4, 4, ".dba") == 0) {
    WriteBinaryProblem(problem, path);
  } else {
    WriteBal(problem, path);
  }
}

}  // namespace dba
