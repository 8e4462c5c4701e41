// BinaryFile: in-order reads across its buffer's refills match the bytes
// written; reads by position; truncation and trailing bytes named with the
// offset and the entry.
#include "dba/io/binary_file.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "dba/common/error.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

std::string WriteBytes(const std::string& name, const std::vector<uint64_t>& values,
                       const std::string& tail = "") {
  const std::string path = dba::testing::TempPath(name);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  std::fwrite(values.data(), 8, values.size(), f);
  std::fwrite(tail.data(), 1, tail.size(), f);
  std::fclose(f);
  return path;
}

TEST(BinaryFile, InOrderAcrossRefillsAndByPosition) {
  std::vector<uint64_t> values(300000);  // 2.4 MB: three refills of 1 MiB
  for (size_t i = 0; i < values.size(); ++i) values[i] = i * 2654435761u;
  BinaryFile f(WriteBytes("binary_file_values.bin", values, std::string("name\0", 5)));
  EXPECT_EQ(f.size(), values.size() * 8 + 5);
  for (size_t i = 0; i < values.size(); ++i) ASSERT_EQ(f.Get<uint64_t>("value"), values[i]) << i;
  EXPECT_EQ(f.String("name"), "name");
  f.ExpectEnd("the name");
  EXPECT_EQ(f.ReadArrayAt<uint64_t>(8 * 131071, 3, "values"),
            (std::vector<uint64_t>{values[131071], values[131072], values[131073]}));
}

TEST(BinaryFile, TruncationNamesOffsetEntryAndSizes) {
  BinaryFile f(WriteBytes("binary_file_short.bin", {7}, "abc"));
  f.SetEntry("image", 3);
  f.SetEntryId(7);
  EXPECT_EQ(f.Get<uint64_t>("id"), 7u);
  try {
    f.Get<uint64_t>("tvec");
    FAIL() << "read past the end";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("at byte 8: file truncated: image #3 (id 7) tvec needs 8 "
                                         "bytes, only 3 left (file size 11)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(f.ReadAt(8, nullptr, 8, "points"), InputError);
}

TEST(BinaryFile, TrailingBytesAndImpossibleCounts) {
  BinaryFile f(WriteBytes("binary_file_count.bin", {1000, 1}));
  EXPECT_THROW(f.Count("the number of images", 24), InputError);  // 1000 x 24 > 8 left
  BinaryFile g(WriteBytes("binary_file_trailing.bin", {1, 2}));
  EXPECT_EQ(g.Get<uint64_t>("first"), 1u);
  EXPECT_THROW(g.ExpectEnd("the first"), InputError);
}

}  // namespace
}  // namespace dba
