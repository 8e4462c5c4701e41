// n doubles that a computation writes afresh each time it runs and forgets
// after it (a linear solve's preconditioner values and vectors): at a place
// the caller lends for a while (storage idle meanwhile, e.g. the LM step's
// candidate points during the solve), or else in storage of their own, which
// is allocated at the first use and whose pages can go back to the system in
// between (ReturnPages).
//
// Thread safety: as a std::vector; data() allocates on first use, so call it
// once before reading from several threads.
#pragma once

#include <cstdint>
#include <vector>

#include "dba/common/memory.h"

namespace dba {

class PlacedDoubles {
 public:
  // The size; storage of its own of another size is freed (allocated again
  // at the next use).
  void Resize(int64_t n) {
    if (n == n_) return;
    n_ = n;
    own_ = {};
  }
  // From now on at `place` (n doubles, contents the caller's to lose);
  // nullptr: in storage of its own again.
  void Place(double* place) { placed_ = place; }

  double* data() {
    if (placed_ != nullptr) return placed_;
    if (static_cast<int64_t>(own_.size()) != n_) own_.resize(n_);
    return own_.data();
  }
  // Read after data() (allocated by then).
  const double* data() const { return placed_ != nullptr ? placed_ : own_.data(); }
  int64_t size() const { return n_; }

  // Own storage's pages back to the system until the next write; a place
  // lent is the lender's.
  void ReturnPages() {
    dba::ReturnPages(own_.data(), static_cast<int64_t>(own_.size() * sizeof(double)));
  }

 private:
  int64_t n_ = 0;
  double* placed_ = nullptr;
  std::vector<double> own_;
};

}  // namespace dba
