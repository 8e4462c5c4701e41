// libcholmod loaded at the first use; see cholmod_library.h.
#ifdef DBA_HAVE_CHOLMOD
#include "dba/solver/cholmod_library.h"

#include "dba/common/blas_threads.h"
#include "dba/common/shared_library.h"

namespace dba {
namespace {

CholmodFunctions Load() {
  static const SharedLibrary library = OpenLibraryWithBlas(DBA_CHOLMOD_SONAME, "the sparse solver (CHOLMOD)");
  CholmodFunctions f;
#define DBA_CHOLMOD_LOAD(name) f.name = library.Symbol<decltype(f.name)>(#name);
  DBA_CHOLMOD_FUNCTIONS(DBA_CHOLMOD_LOAD)
#undef DBA_CHOLMOD_LOAD
  return f;
}

}  // namespace

const CholmodFunctions& Cholmod() {
  static const CholmodFunctions functions = Load();
  return functions;
}

}  // namespace dba

#endif  // DBA_HAVE_CHOLMOD
