// Selected inversion: the entries of Z = S⁻¹ on the pattern of S's sparse
// Cholesky factor, computed from the factor in place of it, without the dense
// inverse (Takahashi, Fagan and Chen 1973), by supernodes (as SelInv, Lin et
// al. 2011). With P S Pᵀ = L Lᵀ and Z in the factor's order, a supernode's
// columns J and the rows R below them (its block column of L: L_JJ lower
// triangular, L_RJ) satisfy, from Lᵀ Z = L⁻¹ read at J's block row,
//
//   L̂    = L_RJ L_JJ⁻¹
//   Z_RJ = −Z_RR L̂
//   Z_JJ = L_JJ⁻ᵀ L_JJ⁻¹ − L̂ᵀ Z_RJ
//
// (one column of width 1: Z_ij = −(1/L_jj) Σ_k L_kj Z_ik, Z_jj = 1/L_jj² −
// (1/L_jj) Σ_k L_kj Z_kj). R is a clique of the filled graph, so Z_RR lies on
// the pattern, in supernodes after this one: the supernodes are computed
// from the last to the first, each in place of the L block it no longer
// needs. Memory: the factor's and one r×r block; work: two dense products per
// supernode, about the factorization's flops. docs/design.md §8.
//
// Thread safety: pure functions on their arguments.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

namespace dba {

// A sparse lower-triangular factor L of P S Pᵀ = L Lᵀ by supernodes: each a
// run of columns sharing their rows below the diagonal, stored as a dense
// column-major block of its rows (its own columns first, then the rest,
// increasing) by its columns. A simplicial factor is supernodes of width 1.
struct SupernodalFactor {
  std::vector<int64_t> perm;       // factor position k holds S's row perm[k]
  std::vector<int64_t> first_column;  // per supernode, and the end: n
  std::vector<int64_t> row_begin;  // per supernode, into rows; and the end
  std::vector<int64_t> rows;
  std::vector<int64_t> value_begin;  // per supernode, into values; and the end
  // The values where the factorization left them (CHOLMOD's memory, not
  // copied), kept by `storage`.
  std::span<double> values;
  std::shared_ptr<void> storage;
  int64_t size() const { return static_cast<int64_t>(perm.size()); }
  int64_t num_supernodes() const { return static_cast<int64_t>(first_column.size()) - 1; }
};

// Values held by the factor itself.
void SetFactorValues(std::vector<double> values, SupernodalFactor* factor);

// Checks the layout (each supernode's rows start with its columns and
// increase, its diagonal positive); std::logic_error otherwise.
void CheckFactorLayout(const SupernodalFactor& factor);

// The multiply-adds InvertOnPattern takes, times 2: per supernode of width w
// and r rows below it, Z_RR L̂ (2 r² w), L̂ and L̂ᵀ Z_RJ (4 r w²), L_JJ⁻¹ and
// Z_JJ (2 w³).
double InversionFlops(const SupernodalFactor& factor);

// Replaces L's values by Z = S⁻¹ on L's pattern (the lower triangle in the
// factor's order; each supernode's diagonal block whole), on `threads`
// threads: the supernodes near the root one after the other, their products
// on every thread; the independent subtrees below them each on a thread.
// The supernodes must be postordered (CHOLMOD's are; so are single
// columns in column order).
void InvertOnPattern(SupernodalFactor* factor, int threads = 1);

// Z's entries by S's indices, after InvertOnPattern.
class InverseOnPattern {
 public:
  explicit InverseOnPattern(SupernodalFactor inverse);
  // (S⁻¹)_ij; std::out_of_range when (i, j) is outside the factor's pattern.
  double At(int64_t i, int64_t j) const;
  int64_t values() const { return static_cast<int64_t>(z_.values.size()); }

 private:
  SupernodalFactor z_;
  std::vector<int64_t> position_;  // S's row i sits at factor position position_[i]
  std::vector<int64_t> supernode_;  // the supernode of each factor column
};

}  // namespace dba
