// BinaryFile: in-order reads across its buffer's refills match the bytes
// written; reads by position; truncation and trailing bytes named with the
// offset and the entry.
#include "dba/io/binary_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
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

// Reads of 64 MiB and more go around the page cache (O_DIRECT, in aligned
// blocks through a buffer of 32 MiB) where the file system allows it, by
// the buffered path elsewhere (tmpfs): the same bytes either way, from
// unaligned offsets, across the buffer's chunks and up to the file's end.
TEST(BinaryFile, LargeReadsAtUnalignedOffsetsMatchTheBytes) {
  std::vector<uint64_t> values((size_t{72} << 20) / 8);  // 72 MiB
  for (size_t i = 0; i < values.size(); ++i) values[i] = i * 0x9E3779B97F4A7C15ull;
  const std::string tail("xyz", 3);  // the file ends off a 4 KiB boundary
  BinaryFile f(WriteBytes("binary_file_large.bin", values, tail));
  for (const int64_t first : {int64_t{0}, int64_t{1}, int64_t{513}}) {
    const int64_t count = static_cast<int64_t>(values.size()) - first;
    const std::vector<uint64_t> read = f.ReadArrayAt<uint64_t>(8 * first, count, "values");
    ASSERT_EQ(read.size(), static_cast<size_t>(count));
    EXPECT_TRUE(std::equal(read.begin(), read.end(), values.begin() + first)) << first;
  }
  // Unaligned by 3 bytes, up to the last byte of the file.
  std::vector<char> bytes(f.size() - 3 - 8 * 4096 + 1);  // one more for the truncation below
  f.ReadAt(3 + 8 * 4096, bytes.data(), static_cast<int64_t>(bytes.size()) - 1, "bytes");
  EXPECT_EQ(std::memcmp(bytes.data(), reinterpret_cast<const char*>(values.data()) + 3 + 8 * 4096,
                        bytes.size() - 4),
            0);
  EXPECT_EQ(std::string(bytes.end() - 4, bytes.end() - 1), tail);
  // One byte past the end is a truncation, named with its offset.
  try {
    f.ReadAt(3 + 8 * 4096, bytes.data(), static_cast<int64_t>(bytes.size()), "bytes");
    FAIL() << "read past the end";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("truncated or unreadable while reading bytes at byte"),
              std::string::npos)
        << e.what();
  }
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
