// CHOLMOD's functions as the sparse solver calls them, from libcholmod
// loaded at the first sparse factorization or analysis
// (common/shared_library.h), with its LAPACK and BLAS: a run that solves
// densely or by PCG without it never loads them, nor starts OpenBLAS's
// threads. Built with DBA_CHOLMOD only.
#pragma once

#include <cholmod.h>

namespace dba {

#define DBA_CHOLMOD_FUNCTIONS(X)                                                               \
  X(cholmod_allocate_dense) X(cholmod_allocate_sparse) X(cholmod_analyze) X(cholmod_analyze_p) \
  X(cholmod_factorize) X(cholmod_finish) X(cholmod_free_dense) X(cholmod_free_factor)          \
  X(cholmod_free_sparse) X(cholmod_malloc) X(cholmod_solve2) X(cholmod_start)

// One pointer per function, named as the function.
struct CholmodFunctions {
#define DBA_CHOLMOD_POINTER(name) decltype(&::name) name = nullptr;
  DBA_CHOLMOD_FUNCTIONS(DBA_CHOLMOD_POINTER)
#undef DBA_CHOLMOD_POINTER
};

// libcholmod (the soname dba was built against), loaded once, thread-safe,
// with the BLAS as common/blas_threads.h loads it; std::runtime_error naming
// it when it does not load.
const CholmodFunctions& Cholmod();

}  // namespace dba
