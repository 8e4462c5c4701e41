// File helpers for tests: whole-file bytes, and scratch files and directories
// private to the test process.
//
// CTest runs every test case as its own process, several at once (ctest -j),
// so a fixed name under /tmp is shared by concurrent tests (and by concurrent
// runs of the suite). Every path here is inside one directory per process,
// made by mkdtemp under $TMPDIR (or /tmp) on first use and removed with
// everything in it when the process exits normally.
//
// Thread safety: TestTempDir is safe to call from several threads (a static
// local); FreshTempDir on the same name from two threads is not.
#pragma once

#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace dba::testing {

// The bytes of a file ("" if it cannot be read).
inline std::string ReadFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Replaces the file with `bytes`; false on failure.
inline bool WriteFileBytes(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
  return out.good();
}

// This process's own scratch directory, e.g. /tmp/dba_test.Ab12Cd: created
// empty on the first call, removed at exit (by the process that made it, not
// by a forked child).
inline const std::string& TestTempDir() {
  struct Root {
    std::string path;
    pid_t owner = ::getpid();
    Root() {
      const char* env = std::getenv("TMPDIR");
      std::string base = env != nullptr && *env != '\0' ? env : "/tmp";
      while (base.size() > 1 && base.back() == '/') base.pop_back();
      std::string pattern = base + "/dba_test.XXXXXX";
      std::vector<char> name(pattern.begin(), pattern.end());
      name.push_back('\0');
      if (::mkdtemp(name.data()) == nullptr) {
        throw std::runtime_error("mkdtemp " + pattern + ": " + std::strerror(errno));
      }
      path = name.data();
    }
    ~Root() {
      if (::getpid() != owner) return;
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static const Root root;
  return root.path;
}

// `name` inside this process's scratch directory (nothing is created).
inline std::string TempPath(const std::string& name) { return TestTempDir() + "/" + name; }

// An empty directory `name` inside this process's scratch directory (emptied
// if an earlier test of the same process used it).
inline std::string FreshTempDir(const std::string& name) {
  const std::string dir = TempPath(name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace dba::testing
