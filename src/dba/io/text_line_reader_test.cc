// Tests of TextLineReader: plain and bzip2 text, detection by content,
// concatenated streams, long lines, and errors for corrupt/unreadable files.
#include "dba/io/text_line_reader.h"

#include <bzlib.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "dba/common/error.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

std::string TempPath(const std::string& name) {
  return dba::testing::TempPath("text_line_reader_test_" + name);
}

void WriteFile(const std::string& path, const std::string& bytes) {
  FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr) << path;
  ASSERT_EQ(std::fwrite(bytes.data(), 1, bytes.size(), f), bytes.size());
  ASSERT_EQ(std::fclose(f), 0);
}

std::string Compress(const std::string& text) {
  std::vector<char> out(text.size() + text.size() / 100 + 1024);
  unsigned int len = static_cast<unsigned>(out.size());
  int rc = BZ2_bzBuffToBuffCompress(out.data(), &len, const_cast<char*>(text.data()),
                                    static_cast<unsigned>(text.size()), 9, 0, 0);
  EXPECT_EQ(rc, BZ_OK);
  return std::string(out.data(), len);
}

std::vector<std::string> ReadAll(const std::string& path) {
  TextLineReader reader(path);
  std::vector<std::string> lines;
  std::string_view line;
  while (reader.ReadLine(&line)) {
    lines.emplace_back(line);
    EXPECT_EQ(reader.line_number(), static_cast<int64_t>(lines.size()));
  }
  EXPECT_FALSE(reader.ReadLine(&line));  // stays at end
  return lines;
}

// Text with many lines, so that it spans several read and decode chunks.
std::string ManyLines(int n) {
  std::string s;
  for (int i = 0; i < n; ++i) s += std::to_string(i) + " " + std::to_string(i * 7) + "\n";
  return s;
}

std::vector<std::string> SplitLines(const std::string& s) {
  std::vector<std::string> lines;
  size_t start = 0;
  while (start < s.size()) {
    size_t nl = s.find('\n', start);
    if (nl == std::string::npos) nl = s.size();
    lines.push_back(s.substr(start, nl - start));
    start = nl + 1;
  }
  return lines;
}

TEST(TextLineReaderTest, PlainTextLinesAndTerminators) {
  std::string path = TempPath("plain.txt");
  WriteFile(path, "a\nbb\r\n\nccc");
  std::vector<std::string> expected = {"a", "bb", "", "ccc"};
  EXPECT_EQ(ReadAll(path), expected);
  EXPECT_FALSE(TextLineReader(path).is_bz2());
}

TEST(TextLineReaderTest, EmptyFileHasNoLines) {
  std::string path = TempPath("empty.txt");
  WriteFile(path, "");
  TextLineReader reader(path);
  std::string_view line;
  EXPECT_FALSE(reader.ReadLine(&line));
  EXPECT_EQ(reader.line_number(), 0);
}

TEST(TextLineReaderTest, DetectsBzip2ByContentNotName) {
  std::string text = "1 2 3\n4 5 6\n";
  std::string compressed_txt = TempPath("really_bz2.txt");
  std::string plain_bz2 = TempPath("really_plain.bz2");
  WriteFile(compressed_txt, Compress(text));
  WriteFile(plain_bz2, text);
  EXPECT_TRUE(TextLineReader(compressed_txt).is_bz2());
  EXPECT_FALSE(TextLineReader(plain_bz2).is_bz2());
  std::vector<std::string> expected = {"1 2 3", "4 5 6"};
  EXPECT_EQ(ReadAll(compressed_txt), expected);
  EXPECT_EQ(ReadAll(plain_bz2), expected);
}

TEST(TextLineReaderTest, ManyChunksPlainAndCompressed) {
  std::string text = ManyLines(300000);  // about 3.6 MB: many buffers
  std::string plain = TempPath("many.txt");
  std::string packed = TempPath("many.txt.bz2");
  WriteFile(plain, text);
  WriteFile(packed, Compress(text));
  std::vector<std::string> expected = SplitLines(text);
  EXPECT_EQ(ReadAll(plain), expected);
  EXPECT_EQ(ReadAll(packed), expected);
}

TEST(TextLineReaderTest, LineLongerThanTheBuffer) {
  std::string text = "head\n" + std::string(3'000'000, 'x') + "\ntail";
  std::string packed = TempPath("long.bz2");
  WriteFile(packed, Compress(text));
  std::vector<std::string> lines = ReadAll(packed);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], "head");
  EXPECT_EQ(lines[1].size(), 3'000'000u);
  EXPECT_EQ(lines[2], "tail");
}

TEST(TextLineReaderTest, ConcatenatedStreamsReadAsOneText) {
  // The first part ends mid-line: the line continues in the second stream.
  std::string a = ManyLines(1000) + "split ";
  std::string b = "line\n" + ManyLines(500);
  std::string path = TempPath("concat.bz2");
  WriteFile(path, Compress(a) + Compress(b));
  EXPECT_EQ(ReadAll(path), SplitLines(a + b));
}

TEST(TextLineReaderTest, CorruptStreamIsAnInputError) {
  std::string packed = Compress(ManyLines(50000));
  for (size_t i = packed.size() / 2; i < packed.size() / 2 + 16; ++i) packed[i] ^= 0x5a;
  std::string path = TempPath("corrupt.bz2");
  WriteFile(path, packed);
  try {
    ReadAll(path);
    FAIL() << "no error for corrupt bzip2 data";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("corrupt bzip2"), std::string::npos) << e.what();
    EXPECT_GE(e.line(), 1);
  }
}

TEST(TextLineReaderTest, TruncatedStreamIsAnInputError) {
  // Several 900 kB bzip2 blocks: the complete ones decode before the cut.
  std::string packed = Compress(ManyLines(300000));
  std::string path = TempPath("truncated.bz2");
  WriteFile(path, packed.substr(0, packed.size() * 3 / 4));
  try {
    ReadAll(path);
    FAIL() << "no error for truncated bzip2 data";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
    EXPECT_GT(e.line(), 1000);  // the lines before the cut were read
  }
}

TEST(TextLineReaderTest, TrailingGarbageAfterStreamIsAnInputError) {
  std::string path = TempPath("trailing.bz2");
  WriteFile(path, Compress("1 2\n3 4\n") + "garbage");
  try {
    ReadAll(path);
    FAIL() << "no error for trailing garbage";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("trailing data"), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), 3);
  }
}

TEST(TextLineReaderTest, MissingFileNamesPathAndSystemError) {
  std::string path = TempPath("does_not_exist.txt");
  try {
    TextLineReader reader(path);
    FAIL() << "no error for a missing file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos)
        << e.what();
  }
}

TEST(TextLineReaderTest, DirectoryIsUnreadable) {
  std::string path = TempPath("a_directory");
  std::filesystem::create_directories(path);
  try {
    TextLineReader reader(path);
    std::string_view line;
    reader.ReadLine(&line);
    FAIL() << "no error for a directory";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("Is a directory"), std::string::npos) << e.what();
  }
}

TEST(TextLineReaderTest, ReadsSharedBalFile) {
  std::string path = DBA_SHARED_DATA_DIR "/bal/problem-49-7776-pre.txt.bz2";
  TextLineReader reader(path);
  EXPECT_TRUE(reader.is_bz2());
  std::string_view line;
  ASSERT_TRUE(reader.ReadLine(&line));
  EXPECT_EQ(line, "49 7776 31843");
  int64_t count = 1;
  while (reader.ReadLine(&line)) ++count;
  EXPECT_EQ(count, 1 + 31843 + 9 * 49 + 3 * 7776);
  EXPECT_EQ(reader.line_number(), count);
}

}  // namespace
}  // namespace dba
