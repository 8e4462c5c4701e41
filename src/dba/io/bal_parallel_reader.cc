// BAL text parsed piece by piece on a pool; see bal_parallel_reader.h.
#include "dba/io/bal_parallel_reader.h"

#include <algorithm>
#include <atomic>
#include <deque>
#include <exception>
#include <filesystem>
#include <memory>
#include <string_view>
#include <vector>

#include "dba/io/point_major_order.h"
#include "dba/io/text_line_reader.h"
#include "dba/io/text_pieces.h"
#include "dba/io/text_tokens.h"
#include "dba/problem/pixel_range.h"

namespace dba {
namespace {

constexpr size_t kMaxJoinedToken = 4096;
constexpr size_t kMaxHeaderText = size_t{16} << 20;
constexpr int64_t kUnknownSizeReserve = int64_t{1} << 22;

// Not a file this reader takes: ReadBal reads it line by line.
struct Irregular {};

// The header's counts, and the index in the file of each section's first
// token: 3 header tokens, 4 per observation, 9 per camera, 3 per point.
struct Layout {
  int64_t cameras = 0, points = 0, observations = 0;
  int64_t cameras_begin = 0, points_begin = 0, end = 0;
};

// The problem's arrays as sized when a job is sent (they are not resized
// while a job runs).
struct Targets {
  int32_t* obs_camera = nullptr;
  double* obs_pixel = nullptr;
  double* cameras = nullptr;
  double* points = nullptr;
};

// The tokens of a piece from `begin` to `end` (each ends before `end`), the
// first of them the file's token `first_token`; `joined` before them when a
// token began in the piece before. `piece` is null for a token that ends the
// file alone.
struct Job {
  std::shared_ptr<const TextPiece> piece;
  std::string joined;
  size_t begin = 0, end = 0;
  int64_t first_token = 0;
  std::vector<int64_t> points;  // the point of each observation whose point it parsed
  std::atomic<bool> done{false};
  bool ok = true;
  std::exception_ptr failure;
};

// Parses the file's tokens from `first` on, one by one, to their places.
class TokenSink {
 public:
  TokenSink(const Layout& layout, const Targets& to, int64_t first, std::vector<int64_t>* points)
      : l_(layout), to_(to), t_(first), points_(points) {
    if (first < l_.cameras_begin) {
      obs_ = (first - 3) / 4;
      field_ = static_cast<int>((first - 3) % 4);
    }
  }
  // False when the token is not what its place needs.
  bool Take(std::string_view token) {
    if (t_ < l_.cameras_begin) {
      if (!TakeObservationField(token)) return false;
    } else {
      double v = 0;
      if (t_ >= l_.end || ParseDouble(token, &v) != NumberStatus::kOk) return false;
      if (t_ < l_.points_begin) {
        to_.cameras[t_ - l_.cameras_begin] = v;
      } else {
        to_.points[t_ - l_.points_begin] = v;
      }
    }
    ++t_;
    return true;
  }

 private:
  bool TakeObservationField(std::string_view token) {
    if (field_ < 2) {
      int64_t v = 0;
      const int64_t limit = field_ == 0 ? l_.cameras : l_.points;
      if (ParseInteger(token, &v) != NumberStatus::kOk || v < 0 || v >= limit) return false;
      if (field_ == 0) {
        to_.obs_camera[obs_] = static_cast<int32_t>(v);
      } else {
        points_->push_back(v);
      }
    } else if (ParseDouble(token, &to_.obs_pixel[2 * obs_ + field_ - 2]) != NumberStatus::kOk) {
      return false;
    } else if (field_ == 3 &&
               !PixelOutOfRange(to_.obs_pixel[2 * obs_], to_.obs_pixel[2 * obs_ + 1]).empty()) {
      return false;  // the line-by-line reader names it
    }
    if (++field_ == 4) {
      field_ = 0;
      ++obs_;
    }
    return true;
  }

  const Layout& l_;
  const Targets to_;
  int64_t t_;
  std::vector<int64_t>* points_;
  int64_t obs_ = 0;
  int field_ = 0;
};

void RunJob(Job* job, const Layout& layout, const Targets& to) {
  TokenSink sink(layout, to, job->first_token, &job->points);
  if (!job->joined.empty() && !sink.Take(job->joined)) {
    job->ok = false;
    return;
  }
  if (job->piece == nullptr) return;
  const char* t = job->piece->text.data();
  size_t p = job->begin;
  const size_t end = job->end;
  for (;;) {
    while (p < end && IsSeparator(t[p])) ++p;
    if (p == end) return;
    size_t q = p + 1;
    while (q < end && !IsSeparator(t[q])) ++q;
    if (!sink.Take(std::string_view(t + p, q - p))) {
      job->ok = false;
      return;
    }
    p = q;
  }
}

// v holds at least `need` elements (at most `limit`), growing by doubling.
template <typename T>
void Grow(std::vector<T>* v, int64_t need, int64_t limit) {
  const int64_t size = static_cast<int64_t>(v->size());
  if (need <= size) return;
  v->resize(static_cast<size_t>(std::min(limit, std::max(need, 2 * size))));
}

// Tokens of the section [begin, end) below token t.
int64_t Below(int64_t t, int64_t begin, int64_t end) {
  return std::clamp(t, begin, end) - begin;
}

class ParallelBalReader {
 public:
  ParallelBalReader(const std::string& path, int threads)
      : path_(path),
        source_(path, threads, [](TextPiece* p) {
          p->counts = CountText(std::string_view(p->text.data(), p->text.size()));
        }),
        max_jobs_(2 * static_cast<size_t>(std::max(1, threads)) + 2) {}
  ~ParallelBalReader() {
    for (const auto& job : jobs_) source_.pool()->WaitUntil([&] { return job->done.load(); });
  }

  Problem Read();

 private:
  std::shared_ptr<const TextPiece> NextPiece();
  void ReadHeader();
  void StartLayout(int64_t cameras, int64_t points, int64_t observations);
  void Track(const TextPiece& piece);
  void Join(const char* text, size_t n);
  void Plan(std::shared_ptr<const TextPiece> piece);
  void Send(std::shared_ptr<Job> job, int64_t tokens);
  void Reserve(int64_t token_end);
  void Retire();
  void Drain() {
    while (!jobs_.empty()) Retire();
  }
  void Finish();

  std::string path_;
  TextPieceSource source_;
  size_t max_jobs_;
  Layout layout_;
  Problem problem_;
  PointMajorOrder order_;
  std::deque<std::shared_ptr<Job>> jobs_;
  std::string carry_;  // a token that goes on in the next piece
  bool carry_open_ = false;
  int64_t next_token_ = 0;
  int64_t line_bytes_ = 0;    // of the last line so far
  char last_[2] = {'\n', '\n'};  // the text's last two bytes
};

std::shared_ptr<const TextPiece> ParallelBalReader::NextPiece() {
  try {
    return source_.Next();
  } catch (const TextDataError&) {
    throw Irregular{};
  }
}

// Line lengths (TextLineReader refuses lines over its limit) and the last
// bytes (a last line without its end is refused when it ends in a value).
void ParallelBalReader::Track(const TextPiece& piece) {
  const std::vector<char>& t = piece.text;
  const TextCounts& c = piece.counts;
  constexpr int64_t kLongLine = static_cast<int64_t>(TextLineReader::kMaxLineBytes) - 16;
  if (c.first_newline == std::string_view::npos) {
    line_bytes_ += static_cast<int64_t>(t.size());
  } else {
    if (line_bytes_ + static_cast<int64_t>(c.first_newline) > kLongLine) throw Irregular{};
    line_bytes_ = static_cast<int64_t>(t.size() - c.last_newline - 1);
  }
  if (line_bytes_ > kLongLine) throw Irregular{};
  last_[0] = t.size() >= 2 ? t[t.size() - 2] : last_[1];
  last_[1] = t.back();
}

void ParallelBalReader::ReadHeader() {
  std::string head;
  size_t at = 0;  // after the third token
  for (;;) {
    std::shared_ptr<const TextPiece> piece = NextPiece();
    if (piece != nullptr) {
      Track(*piece);
      if (head.size() + piece->text.size() > kMaxHeaderText) throw Irregular{};
      head.append(piece->text.begin(), piece->text.end());
    }
    int64_t counts[3] = {0, 0, 0};
    size_t p = 0;
    int found = 0;
    for (; found < 3; ++found) {
      while (p < head.size() && IsSeparator(head[p])) ++p;
      size_t q = p;
      while (q < head.size() && !IsSeparator(head[q])) ++q;
      if (q == p || (q == head.size() && piece != nullptr)) break;  // more may come
      if (ParseInteger(std::string_view(head).substr(p, q - p), &counts[found]) !=
          NumberStatus::kOk) {
        throw Irregular{};
      }
      p = q;
    }
    if (found == 3) {
      StartLayout(counts[0], counts[1], counts[2]);
      at = p;
      break;
    }
    if (piece == nullptr) throw Irregular{};
  }
  auto rest = std::make_shared<TextPiece>();
  rest->text.assign(head.begin() + static_cast<std::ptrdiff_t>(at), head.end());
  if (rest->text.empty()) return;
  rest->counts = CountText(std::string_view(rest->text.data(), rest->text.size()));
  Plan(std::move(rest));
}

void ParallelBalReader::StartLayout(int64_t cameras, int64_t points, int64_t observations) {
  if (cameras <= 0 || cameras > kMaxBalCameras || points <= 0 || observations <= 0 ||
      points > observations) {
    throw Irregular{};
  }
  Layout& l = layout_;
  l.cameras = cameras;
  l.points = points;
  l.observations = observations;
  l.cameras_begin = 3 + 4 * observations;
  l.points_begin = l.cameras_begin + kBalCameraSize * cameras;
  l.end = l.points_begin + kPointSize * points;
  next_token_ = 3;
  // Sized from the header as far as the file can hold it (a value takes two
  // bytes, an observation eight; BAL text compresses 3-5x, 64x bounds it);
  // beyond, the arrays grow as data comes.
  std::error_code ec;
  const auto size = std::filesystem::file_size(path_, ec);
  const int64_t content =
      ec ? 8 * kUnknownSizeReserve : static_cast<int64_t>(size) * (source_.is_bz2() ? 64 : 1);
  Grow(&problem_.obs_camera, content / 8 + 1, observations);
  Grow(&problem_.obs_pixel, 2 * (content / 8 + 1), 2 * observations);
  Grow(&problem_.cameras, content / 2 + 1, kBalCameraSize * cameras);
  Grow(&problem_.points, content / 2 + 1, kPointSize * points);
}

void ParallelBalReader::Join(const char* text, size_t n) {
  if (carry_.size() + n > kMaxJoinedToken) throw Irregular{};
  carry_.append(text, n);
}

// The piece's tokens as a job: the token the piece before left open joined
// with the piece's first bytes, and the piece's last token kept open when it
// runs to the piece's end.
void ParallelBalReader::Plan(std::shared_ptr<const TextPiece> piece) {
  const std::vector<char>& t = piece->text;
  const TextCounts& c = piece->counts;
  constexpr size_t npos = std::string_view::npos;
  auto job = std::make_shared<Job>();
  int64_t tokens = c.tokens;
  size_t begin = 0;
  if (carry_open_) {
    if (c.first_separator == npos) return Join(t.data(), t.size());
    Join(t.data(), c.first_separator);
    job->joined.swap(carry_);
    carry_.clear();
    carry_open_ = false;
    begin = c.first_separator;
    if (!IsSeparator(t[0])) --tokens;
  }
  size_t end = t.size();
  if (!IsSeparator(t.back())) {
    end = c.last_separator == npos ? 0 : c.last_separator + 1;
    Join(t.data() + end, t.size() - end);
    carry_open_ = true;
    --tokens;
  }
  if (!job->joined.empty()) ++tokens;
  if (tokens == 0) return;
  job->piece = std::move(piece);
  job->begin = begin;
  job->end = std::max(begin, end);
  Send(std::move(job), tokens);
}

void ParallelBalReader::Send(std::shared_ptr<Job> job, int64_t tokens) {
  job->first_token = next_token_;
  next_token_ += tokens;
  Reserve(next_token_);
  if (job->first_token < layout_.cameras_begin) job->points.reserve(tokens / 4 + 1);
  const Targets to{problem_.obs_camera.data(), problem_.obs_pixel.data(),
                   problem_.cameras.data(), problem_.points.data()};
  jobs_.push_back(job);  // first: the destructor waits for every job sent
  try {
    source_.pool()->Submit(
        [job = std::move(job), to, layout = layout_] {
          try {
            RunJob(job.get(), layout, to);
          } catch (...) {
            job->failure = std::current_exception();
          }
          job->done.store(true);
        },
        true);
  } catch (...) {
    jobs_.pop_back();  // not sent
    throw;
  }
}

// The arrays hold every place of the tokens below token_end; to grow them
// the jobs sent are finished first.
void ParallelBalReader::Reserve(int64_t token_end) {
  const Layout& l = layout_;
  if (token_end > l.end) throw Irregular{};  // more data than the header says
  const int64_t obs = (Below(token_end, 3, l.cameras_begin) + 3) / 4;
  const int64_t cameras = Below(token_end, l.cameras_begin, l.points_begin);
  const int64_t points = Below(token_end, l.points_begin, l.end);
  if (obs <= static_cast<int64_t>(problem_.obs_camera.size()) &&
      cameras <= static_cast<int64_t>(problem_.cameras.size()) &&
      points <= static_cast<int64_t>(problem_.points.size())) {
    return;
  }
  Drain();
  Grow(&problem_.obs_camera, obs, l.observations);
  Grow(&problem_.obs_pixel, 2 * obs, 2 * l.observations);
  Grow(&problem_.cameras, cameras, kBalCameraSize * l.cameras);
  Grow(&problem_.points, points, kPointSize * l.points);
}

void ParallelBalReader::Retire() {
  const Job& job = *jobs_.front();
  if (!job.done.load()) source_.pool()->WaitUntil([&] { return job.done.load(); });
  if (job.failure) std::rethrow_exception(job.failure);
  if (!job.ok) throw Irregular{};
  for (int64_t k : job.points) order_.Add(k);
  jobs_.pop_front();
}

Problem ParallelBalReader::Read() {
  ReadHeader();
  while (std::shared_ptr<const TextPiece> piece = NextPiece()) {
    Track(*piece);
    Plan(std::move(piece));
    while (jobs_.size() > max_jobs_) Retire();
  }
  if (carry_open_) {  // the file's last token, cut between pieces
    auto job = std::make_shared<Job>();
    job->joined.swap(carry_);
    carry_open_ = false;
    Send(std::move(job), 1);
  }
  Drain();
  Finish();
  return std::move(problem_);
}

void ParallelBalReader::Finish() {
  const Layout& l = layout_;
  if (next_token_ != l.end) throw Irregular{};  // less data than the header says
  // A last line without its end that ends in a value (its '\r' aside).
  const char last = last_[1] == '\r' ? last_[0] : last_[1];
  if (last_[1] != '\n' && !IsSeparator(last)) throw Irregular{};
  for (int64_t k = 0; k < l.points; ++k) {
    if (order_.count(k) == 0) throw Irregular{};  // a point without observations
  }
  order_.Finish(l.points, &problem_);
  problem_.obs_camera.shrink_to_fit();
  problem_.obs_pixel.shrink_to_fit();
  problem_.cameras.shrink_to_fit();
  problem_.points.shrink_to_fit();
}

}  // namespace

std::optional<Problem> ReadBalInParallel(const std::string& path, int threads) {
  try {
    ParallelBalReader reader(path, threads);
    return reader.Read();
  } catch (const Irregular&) {
    return std::nullopt;
  }
}

}  // namespace dba
