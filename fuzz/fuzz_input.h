// What the fuzz targets share: the fuzzer's bytes as files the readers open
// (they take paths), in a directory private to the process, and the rule
// that a reader may refuse any input (an exception) but never crash, hang or
// allocate without bound.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace dba::fuzz {

// This process's scratch directory (made once).
inline const std::string& Dir() {
  static const std::string dir = [] {
    char name[] = "/tmp/dba_fuzz.XXXXXX";
    if (::mkdtemp(name) == nullptr) std::abort();
    return std::string(name);
  }();
  return dir;
}

inline void WriteFile(const std::string& path, std::string_view bytes) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) std::abort();
  std::fwrite(bytes.data(), 1, bytes.size(), f);
  std::fclose(f);
}

// The input cut at `separator` bytes into at most `parts` pieces (the last
// takes the rest; missing pieces are empty): one fuzz input, several files.
inline std::vector<std::string_view> Split(const uint8_t* data, size_t size, int parts,
                                           char separator = '\0') {
  std::vector<std::string_view> out;
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  for (int p = 0; p + 1 < parts; ++p) {
    const size_t at = rest.find(separator);
    if (at == std::string_view::npos) {
      out.push_back(rest);
      rest = {};
    } else {
      out.push_back(rest.substr(0, at));
      rest = rest.substr(at + 1);
    }
  }
  out.push_back(rest);
  return out;
}

}  // namespace dba::fuzz
