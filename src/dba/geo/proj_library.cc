// libproj loaded at the first use; see proj_library.h.
#include "dba/geo/proj_library.h"

#include "dba/common/shared_library.h"

namespace dba {
namespace {

ProjFunctions Load() {
  static const SharedLibrary library(DBA_PROJ_SONAME, "a coordinate reference system (PROJ)");
  ProjFunctions f;
#define DBA_PROJ_LOAD(name) f.name = library.Symbol<decltype(f.name)>(#name);
  DBA_PROJ_FUNCTIONS(DBA_PROJ_LOAD)
#undef DBA_PROJ_LOAD
  return f;
}

}  // namespace

const ProjFunctions& Proj() {
  static const ProjFunctions functions = Load();
  return functions;
}

}  // namespace dba
