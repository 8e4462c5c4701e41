// PROJ's functions as dba calls them, from libproj loaded at the first use
// (common/shared_library.h): a run without a coordinate reference system
// never loads it and the 40 libraries it brings.
#pragma once

#include <proj.h>

namespace dba {

#define DBA_PROJ_FUNCTIONS(X)                                                                   \
  X(proj_context_create)                                                                        \
  X(proj_context_destroy) X(proj_context_errno) X(proj_context_errno_string) X(proj_coord)      \
  X(proj_coordoperation_has_ballpark_transformation) X(proj_create)                            \
  X(proj_create_crs_to_crs_from_pj) X(proj_crs_get_coordinate_system) X(proj_crs_get_sub_crs)  \
  X(proj_cs_get_axis_count) X(proj_destroy) X(proj_get_type) X(proj_is_crs) X(proj_log_func)   \
  X(proj_pj_info) X(proj_trans) X(proj_trans_get_last_used_operation)

// One pointer per function, named as the function.
struct ProjFunctions {
#define DBA_PROJ_POINTER(name) decltype(&::name) name = nullptr;
  DBA_PROJ_FUNCTIONS(DBA_PROJ_POINTER)
#undef DBA_PROJ_POINTER
};

// libproj (the soname dba was built against), loaded once, thread-safe;
// std::runtime_error naming it when it does not load.
const ProjFunctions& Proj();

}  // namespace dba
