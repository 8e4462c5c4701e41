// A shared library opened when first needed (dlopen), for the dependencies
// only some runs use: PROJ (georeferencing) and CHOLMOD with its BLAS (the
// sparse solver). Linked into the program they cost every run their loading
// and relocation, about 8 ms (PROJ and the network, TLS and image libraries
// it brings) and 10 ms (CHOLMOD, LAPACK and OpenBLAS starting its threads)
// of a 5-image problem's 25 ms, twice over when dba starts again with the
// libraries' environment (tools/dba_main.cc); bench/README.md, "Start-up".
//
// A library stays loaded to the process's end (OpenBLAS's threads and
// PROJ's caches do not survive an unload).
#pragma once

#include <cstdint>
#include <string>

namespace dba {

// What the libraries opened so far added to the process's resident memory
// (measured around each opening), for the memory estimate: CHOLMOD with its
// BLAS about 8 MiB. Thread-safe.
int64_t SharedLibrariesResidentBytes();

class SharedLibrary {
 public:
  // Opens `soname` with its dependencies; `global` makes its symbols and its
  // dependencies' visible to dlsym(RTLD_DEFAULT). std::runtime_error naming
  // the library, what it is for (`purpose`, e.g. "georeferencing") and why
  // it did not load.
  SharedLibrary(const std::string& soname, const std::string& purpose, bool global = false);

  // The symbol `name` as a `T` (a function pointer type); std::runtime_error
  // naming the symbol and the library when it has none.
  template <typename T>
  T Symbol(const char* name) const {
    return reinterpret_cast<T>(Address(name));
  }

 private:
  void* Address(const char* name) const;

  std::string soname_;
  void* handle_ = nullptr;
};

}  // namespace dba
