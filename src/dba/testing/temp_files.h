// File helpers for tests: whole-file bytes, and fresh scratch directories
// private to the test process and removed when it exits.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

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

// An empty directory `name` under a per-process root in `base` (the test
// framework's temporary directory), removed with everything in it at exit.
inline std::string FreshTempDir(const std::string& base, const std::string& name) {
  struct Root {
    std::string path;
    ~Root() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static Root root{base + "/dba_test_" + std::to_string(::getpid())};
  const std::string dir = root.path + "/" + name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace dba::testing
