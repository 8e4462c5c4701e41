// Atomic whole-file write; see atomic_file.h.
#include "dba/io/atomic_file.h"

#include <cerrno>

#include "dba/io/temporary_file.h"

namespace dba {

void WriteFileAtomically(const std::string& path, std::string_view contents) {
  TemporaryFile out(path);
  if (std::fwrite(contents.data(), 1, contents.size(), out.file()) != contents.size()) {
    out.Fail("write failed", errno);
  }
  out.Commit();
}

}  // namespace dba
