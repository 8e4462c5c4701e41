// A preconditioner M ≈ S for PCG (paper eq. 7). Lifecycle: constructed once
// per LM solve from the structure of S (symbolic: storage, orderings), then
// per linear solve Update(S) with the damped values (numeric), then any
// number of Apply calls.
//
// Thread safety: Apply is const and may use its own threads; Update is not
// concurrent with Apply.
#pragma once

#include <cstdint>

#include "dba/bsmc/bsmc_matrix.h"

namespace dba {

class Preconditioner {
 public:
  virtual ~Preconditioner() = default;
  // Numeric phase on S's current values (same structure as at construction).
  virtual void Update(const BsmcMatrix& S) = 0;
  // z = M⁻¹ r.
  virtual void Apply(const double* r, double* z) const = 0;
  virtual int64_t MemoryBytes() const = 0;
  // Between solves (the LM loop forms the next RCS meanwhile): the pages of
  // what Update computes go back to the system until the next Update.
  virtual void ReturnNumericPages() {}
};

}  // namespace dba
