// BAL text parsed on the run's threads (docs/design.md §4.3). The text comes
// in pieces from io/text_pieces (bzip2 blocks decoded on the same threads);
// each piece's tokens are counted where it is decoded, so the reader knows
// which token of the file every piece starts with and hence what each of
// its tokens is (an observation's camera, point or pixel, a camera
// parameter, a point coordinate) before parsing it: the pieces are parsed
// in parallel, each value written straight to its place. A token cut
// between two pieces is joined and parsed with the second. The observations'
// points go to io/point_major_order in file order, piece by piece.
//
// It takes only files that are well-formed BAL: on any error (a bad token,
// counts that do not match the data, a line over TextLineReader's limit, a
// last line without its end, corrupt bzip2 data) it returns nullopt, and
// ReadBal reads the file again line by line for the message naming the
// line. Tokens longer than 4 KiB cut between pieces go that way too.
//
// Thread safety: one call per file; it runs its own threads.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "dba/problem/problem.h"

namespace dba {

// A BAL file's most cameras: camera ids are int32 (both readers' bound).
inline constexpr int64_t kMaxBalCameras = int64_t{1} << 31;

// The problem, the same bits on any number of threads (>= 1); nullopt when
// the file is not one this reader takes (see above). Throws InputError when
// the file cannot be opened.
std::optional<Problem> ReadBalInParallel(const std::string& path, int threads);

}  // namespace dba
