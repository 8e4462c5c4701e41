// BAL text writer with atomic replace (write temporary, fsync, rename); see
// bal_writer.h.
#include "dba/io/bal_writer.h"

#include <bzlib.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string_view>

#include "dba/io/path_kind.h"
#include "dba/io/atomic_output_file.h"

namespace dba {
namespace {

constexpr size_t kFlushBytes = size_t{1} << 20;

void CheckConsistent(const Problem& p) {
  const int64_t n = p.num_observations();
  bool ok = p.cameras.size() % kBalCameraSize == 0 &&
            p.points.size() % kPointSize == 0 &&
            static_cast<int64_t>(p.point_offsets.size()) == p.num_points() + 1 &&
            p.point_offsets.front() == 0 && p.point_offsets.back() == n &&
            static_cast<int64_t>(p.obs_pixel.size()) == 2 * n;
  for (size_t k = 0; ok && k + 1 < p.point_offsets.size(); ++k) {
    ok = p.point_offsets[k] <= p.point_offsets[k + 1];
  }
  for (int64_t j = 0; ok && j < n; ++j) {
    ok = p.obs_camera[j] >= 0 && p.obs_camera[j] < p.num_images();
  }
  if (!ok) throw std::invalid_argument("WriteBal: inconsistent Problem arrays");
}

// Buffered output to a plain or bzip2 file, through a AtomicOutputFile that is
// renamed over the path by Commit() and removed otherwise.
class Output {
 public:
  Output(const std::string& path, bool bz2) : out_(path) {
    if (bz2) {
      int err = BZ_OK;
      bz_ = BZ2_bzWriteOpen(&err, out_.file(), 9, 0, 0);
      if (err != BZ_OK) out_.Fail("cannot start bzip2 compression", 0);
    }
    buf_.reserve(kFlushBytes + 256);
  }

  ~Output() {
    if (bz_ != nullptr) {
      // libbz2 returns early, leaking its state, while the FILE has its error
      // flag set; clear it so the abandoning close frees everything.
      std::clearerr(out_.file());
      int err;
      BZ2_bzWriteClose64(&err, bz_, /*abandon=*/1, nullptr, nullptr, nullptr, nullptr);
    }
  }

  void Int(int64_t v, char sep) {
    char s[24];
    auto r = std::to_chars(s, s + sizeof s, v);
    buf_.append(s, r.ptr);
    Append(sep);
  }

  void Double(double v, char sep) {
    if (!std::isfinite(v)) {
      throw std::invalid_argument("WriteBal: refusing to write non-finite value");
    }
    char s[32];
    auto r = std::to_chars(s, s + sizeof s, v);  // shortest round-trip form
    buf_.append(s, r.ptr);
    Append(sep);
  }

  // Flushes, closes, fsyncs and renames the temporary over the path.
  void Commit() {
    Flush();
    if (bz_ != nullptr) {
      int err = BZ_OK;
      errno = 0;
      BZ2_bzWriteClose64(&err, bz_, 0, nullptr, nullptr, nullptr, nullptr);
      if (err != BZ_OK) out_.Fail("bzip2 write failed", errno);  // bz_ still open
      bz_ = nullptr;
    }
    out_.Commit();
  }

 private:
  void Append(char c) {
    buf_.push_back(c);
    if (buf_.size() >= kFlushBytes) Flush();
  }

  void Flush() {
    if (buf_.empty()) return;
    errno = 0;
    if (bz_ != nullptr) {
      int err = BZ_OK;
      BZ2_bzWrite(&err, bz_, buf_.data(), static_cast<int>(buf_.size()));
      if (err != BZ_OK) out_.Fail("bzip2 write failed", errno);
    } else if (std::fwrite(buf_.data(), 1, buf_.size(), out_.file()) != buf_.size()) {
      out_.Fail("write failed", errno);
    }
    buf_.clear();
  }

  AtomicOutputFile out_;
  BZFILE* bz_ = nullptr;
  std::string buf_;
};

}  // namespace

void WriteBal(const Problem& problem, const std::string& path) {
  if (problem.model != CameraModel::kBal) {
    throw std::invalid_argument(
        "cannot write " + path + " as BAL text: a photogrammetric problem (" +
        std::to_string(problem.num_images()) + " image poses sharing " +
        std::to_string(problem.num_groups()) +
        " intrinsic groups) has no BAL form, the BAL format cannot hold shared intrinsics; "
        "write the dba binary format (.dba) instead");
  }
  CheckConsistent(problem);
  Output out(path, KindOfPath(path) == PathKind::kBalBz2);
  out.Int(problem.num_images(), ' ');
  out.Int(problem.num_points(), ' ');
  out.Int(problem.num_observations(), '\n');
  for (int64_t k = 0; k < problem.num_points(); ++k) {
    for (int64_t j = problem.point_offsets[k]; j < problem.point_offsets[k + 1]; ++j) {
      out.Int(problem.obs_camera[j], ' ');
      out.Int(k, ' ');
      out.Double(problem.obs_pixel[2 * j], ' ');
      out.Double(problem.obs_pixel[2 * j + 1], '\n');
    }
  }
  for (double v : problem.cameras) out.Double(v, '\n');
  for (double v : problem.points) out.Double(v, '\n');
  out.Commit();
}

}  // namespace dba
