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
  // What Update computes afresh each time (e.g. block-Jacobi's inverses,
  // for the Applys after it; a coarse matrix's values, for its
  // factorization): NumericDoubles() doubles, placed
  // where the caller lends them for the next Update and its Applys
  // (PlaceNumeric; nullptr: storage of its own again), else in storage of
  // its own, allocated at the first Update.
  virtual int64_t NumericDoubles() const { return 0; }
  virtual void PlaceNumeric(double* place) { (void)place; }
  // Between solves (the LM loop forms the next RCS meanwhile): the pages of
  // what Update computes in storage of its own go back to the system until
  // the next Update.
  virtual void ReturnNumericPages() {}
};

}  // namespace dba
