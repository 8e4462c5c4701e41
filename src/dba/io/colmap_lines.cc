// The lines and tokens of COLMAP's text files; see colmap_lines_internal.h.
#include "dba/io/colmap_lines_internal.h"

#include <limits>

#include "dba/common/error.h"
#include "dba/io/colmap_model_internal.h"

namespace dba {
namespace colmap_internal {

std::string Quote(std::string_view tok) {
  std::string q(1, '\'');
  q.append(tok.substr(0, 40));
  q.append(tok.size() > 40 ? "...'" : "'");
  return q;
}

bool LineFile::Next(std::string_view* line) {
  if (!reader_.ReadLine(line)) return false;
  if (reader_.last_line_unterminated() && !TrimBlanks(*line).empty()) {
    Fail("the file ends inside this line (no line end after the last record): cut short?");
  }
  return true;
}

bool LineFile::NextData(std::string_view* line) {
  while (Next(line)) {
    std::string_view t = TrimBlanks(*line);
    if (!t.empty() && t.front() != '#') {
      *line = t;
      return true;
    }
  }
  return false;
}

void LineFile::Fail(const std::string& what) const { throw InputError(path(), line_number(), what); }

std::string_view Tokens::Next(const char* what) {
  std::string_view tok;
  if (!tokens_.Next(&tok)) file_.Fail(std::string("expected ") + what + ", found the end of the line");
  return tok;
}

void Tokens::End() const {
  if (const int left = tokens_.Remaining(); left > 0) {
    file_.Fail(std::to_string(left) + " fields after the entry's last, from " + Quote(Rest()));
  }
}

double Tokens::Double(const char* what) {
  const std::string_view tok = Next(what);
  double v = 0;
  const NumberStatus status = ParseDouble(tok, &v);
  if (status == NumberStatus::kNotFinite) {
    file_.Fail(std::string(what) + " is not finite: " + Quote(tok));
  }
  if (status != NumberStatus::kOk) {
    file_.Fail(std::string("expected ") + what + " (a number), found " + Quote(tok));
  }
  return v;
}

void Tokens::Pose(const char* what, std::array<double, 4>* q, std::array<double, 3>* t) {
  static const char* const kQ[] = {"QW", "QX", "QY", "QZ"};
  static const char* const kT[] = {"TX", "TY", "TZ"};
  for (int k = 0; k < 4; ++k) (*q)[k] = Double(kQ[k]);
  if (!IsRotationQuaternion(*q)) file_.Fail(what + std::string(kNotARotation));
  for (int k = 0; k < 3; ++k) (*t)[k] = Double(kT[k]);
}

uint64_t Tokens::Unsigned(const char* what, uint64_t max) {
  const std::string_view tok = Next(what);
  uint64_t v = 0;
  if (ParseInteger(tok, &v) != NumberStatus::kOk || v > max) {
    file_.Fail(std::string("expected ") + what + " (an integer from 0 to " + std::to_string(max) +
               "), found " + Quote(tok));
  }
  return v;
}

int64_t Tokens::Point3DRef(const char* what) {
  const std::string_view tok = Next(what);
  int64_t v = 0;
  if (ParseInteger(tok, &v) == NumberStatus::kOk && v >= -1) return v;
  uint64_t u = 0;
  if (ParseInteger(tok, &u) == NumberStatus::kOk && u == std::numeric_limits<uint64_t>::max()) {
    return kColmapNoPoint3D;
  }
  file_.Fail(std::string("expected ") + what + " (-1 or a point3D_id), found " + Quote(tok));
}

}  // namespace colmap_internal
}  // namespace dba
