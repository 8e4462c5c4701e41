// Takahashi's recursion by supernodes; see selected_inversion.h.
#include "dba/solver/selected_inversion.h"

#include <Eigen/Core>
#include <Eigen/Dense>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace dba {
namespace {

using Matrix = Eigen::MatrixXd;
using Block = Eigen::Map<Matrix>;

std::vector<int64_t> SupernodeOfColumns(const SupernodalFactor& f) {
  std::vector<int64_t> of(f.size());
  for (int64_t s = 0; s < f.num_supernodes(); ++s) {
    std::fill(of.begin() + f.first_column[s], of.begin() + f.first_column[s + 1], s);
  }
  return of;
}

int64_t RowCount(const SupernodalFactor& f, int64_t s) { return f.row_begin[s + 1] - f.row_begin[s]; }

// Z_RR (r×r) of supernode s's rows R below its columns, from the supernodes
// after it: each column c of R lies in supernode t, whose rows hold R's
// rows from c on (R is a clique), found by one merge per t.
void GatherZrr(const SupernodalFactor& f, const std::vector<int64_t>& supernode, int64_t s,
               std::vector<int64_t>* position, Matrix* zrr) {
  const int64_t width = f.first_column[s + 1] - f.first_column[s];
  const int64_t* R = f.rows.data() + f.row_begin[s] + width;
  const int64_t r = RowCount(f, s) - width;
  zrr->resize(r, r);
  position->resize(r);
  for (int64_t a = 0; a < r;) {
    const int64_t t = supernode[R[a]];
    int64_t p = f.row_begin[t];
    for (int64_t q = a; q < r; ++q) {
      while (p < f.row_begin[t + 1] && f.rows[p] < R[q]) ++p;
      if (p == f.row_begin[t + 1] || f.rows[p] != R[q]) {
        throw std::logic_error("selected inversion: the factor's pattern is not filled (row " +
                               std::to_string(R[q]) + " of supernode " + std::to_string(t) + ")");
      }
      (*position)[q] = p - f.row_begin[t];
    }
    const int64_t nsrow = RowCount(f, t);
    for (; a < r && supernode[R[a]] == t; ++a) {
      const double* z = f.values.data() + f.value_begin[t] + (R[a] - f.first_column[t]) * nsrow;
      for (int64_t q = a; q < r; ++q) (*zrr)(q, a) = (*zrr)(a, q) = z[(*position)[q]];
    }
  }
}

}  // namespace

void SetFactorValues(std::vector<double> values, SupernodalFactor* f) {
  auto held = std::make_shared<std::vector<double>>(std::move(values));
  f->values = std::span<double>(*held);
  f->storage = std::move(held);
}

void CheckFactorLayout(const SupernodalFactor& f) {
  for (int64_t s = 0; s < f.num_supernodes(); ++s) {
    const int64_t width = f.first_column[s + 1] - f.first_column[s];
    const int64_t nsrow = RowCount(f, s);
    bool ok = width >= 1 && nsrow >= width && f.value_begin[s + 1] - f.value_begin[s] == nsrow * width;
    for (int64_t a = 0; ok && a < nsrow; ++a) {
      const int64_t row = f.rows[f.row_begin[s] + a];
      ok = a < width ? row == f.first_column[s] + a : row > f.rows[f.row_begin[s] + a - 1];
      if (ok && a < width) ok = f.values[f.value_begin[s] + a * nsrow + a] > 0.0;
    }
    if (!ok) {
      throw std::logic_error("Cholesky factor: supernode " + std::to_string(s) +
                             " is not laid out as its columns, then increasing rows, positive diagonal");
    }
  }
}

double SupernodeFlops(const SupernodalFactor& f, int64_t s) {
  const double w = static_cast<double>(f.first_column[s + 1] - f.first_column[s]);
  const double r = static_cast<double>(RowCount(f, s)) - w;
  return 2 * r * r * w + 4 * r * w * w + 2 * w * w * w;
}

double InversionFlops(const SupernodalFactor& f) {
  double flops = 0.0;
  for (int64_t s = 0; s < f.num_supernodes(); ++s) flops += SupernodeFlops(f, s);
  return flops;
}

namespace {

// One supernode's block of Z in place of its block of L (selected_inversion.h).
void InvertSupernode(SupernodalFactor* factor, const std::vector<int64_t>& supernode, int64_t s,
                     std::vector<int64_t>* position, Matrix* zrr) {
  SupernodalFactor& f = *factor;
  const int64_t w = f.first_column[s + 1] - f.first_column[s];
  const int64_t nsrow = RowCount(f, s);
  const int64_t r = nsrow - w;
  Block L(f.values.data() + f.value_begin[s], nsrow, w);
  const Matrix l_jj = L.topRows(w).triangularView<Eigen::Lower>();
  const Matrix l_inv = l_jj.triangularView<Eigen::Lower>().solve(Matrix::Identity(w, w));
  Matrix z_jj = l_inv.transpose() * l_inv;
  if (r > 0) {
    const Matrix l_hat = L.bottomRows(r) * l_inv;
    GatherZrr(f, supernode, s, position, zrr);
    const Matrix z_rj = -(*zrr) * l_hat;
    z_jj.noalias() -= l_hat.transpose() * z_rj;
    L.bottomRows(r) = z_rj;
  }
  L.topRows(w) = 0.5 * (z_jj + z_jj.transpose());
}

// The supernodes (postordered: a subtree is a range ending at its root) whose
// subtree takes at least `share` of the flops form a top subtree, done one
// after the other with the products on every thread; the subtrees below
// them are independent of each other (each reads only its ancestors) and go
// to the threads whole. Returns the roots of those subtrees and their sizes
// (none, everything in the top, when the supernodes are not postordered).
std::vector<std::pair<int64_t, int64_t>> SplitTree(const SupernodalFactor& f,
                                                   const std::vector<int64_t>& supernode, double share,
                                                   std::vector<uint8_t>* top) {
  const int64_t ns = f.num_supernodes();
  std::vector<double> flops(ns, 0.0);
  std::vector<int64_t> size(ns, 1), parent(ns, -1);
  double total = 0.0;
  for (int64_t s = 0; s < ns; ++s) {
    const int64_t w = f.first_column[s + 1] - f.first_column[s];
    if (RowCount(f, s) > w) parent[s] = supernode[f.rows[f.row_begin[s] + w]];
    flops[s] += SupernodeFlops(f, s);
    total += SupernodeFlops(f, s);
    if (parent[s] >= 0) flops[parent[s]] += flops[s], size[parent[s]] += size[s];
  }
  top->assign(ns, 0);
  std::vector<std::pair<int64_t, int64_t>> subtrees;
  for (int64_t s = 0; s < ns; ++s) {
    if (parent[s] >= 0 && (parent[s] <= s || s <= parent[s] - size[parent[s]])) {
      top->assign(ns, 1);  // not postordered: one after the other
      return subtrees;
    }
  }
  for (int64_t s = ns - 1; s >= 0; --s) {
    if (flops[s] >= share * total && (parent[s] < 0 || (*top)[parent[s]])) {
      (*top)[s] = 1;
    } else if (parent[s] < 0 || (*top)[parent[s]]) {
      subtrees.push_back({s, size[s]});
    }
  }
  return subtrees;
}

}  // namespace

void InvertOnPattern(SupernodalFactor* factor, int threads) {
  const std::vector<int64_t> supernode = SupernodeOfColumns(*factor);
  std::vector<uint8_t> top;
  const auto subtrees = SplitTree(*factor, supernode, 1.0 / (8.0 * std::max(1, threads)), &top);
  std::vector<int64_t> position;
  Matrix zrr;
  for (int64_t s = factor->num_supernodes() - 1; s >= 0; --s) {
    if (top[s]) InvertSupernode(factor, supernode, s, &position, &zrr);
  }
  const int64_t count = static_cast<int64_t>(subtrees.size());
#pragma omp parallel num_threads(std::max(1, threads)) if (threads > 1)
  {
    std::vector<int64_t> own_position;
    Matrix own_zrr;
#pragma omp for schedule(dynamic, 1)
    for (int64_t k = 0; k < count; ++k) {
      const auto [root, size] = subtrees[k];
      for (int64_t s = root; s > root - size; --s) InvertSupernode(factor, supernode, s, &own_position, &own_zrr);
    }
  }
}

InverseOnPattern::InverseOnPattern(SupernodalFactor inverse)
    : z_(std::move(inverse)), supernode_(SupernodeOfColumns(z_)) {
  position_.resize(z_.size());
  for (int64_t k = 0; k < z_.size(); ++k) position_[z_.perm[k]] = k;
}

double InverseOnPattern::At(int64_t i, int64_t j) const {
  int64_t a = position_[i], b = position_[j];
  if (a < b) std::swap(a, b);
  const int64_t t = supernode_[b];
  const auto first = z_.rows.begin() + z_.row_begin[t];
  const auto last = z_.rows.begin() + z_.row_begin[t + 1];
  const auto it = std::lower_bound(first, last, a);
  if (it == last || *it != a) {
    throw std::out_of_range("S⁻¹(" + std::to_string(i) + ", " + std::to_string(j) +
                            ") is outside the factor's pattern");
  }
  const int64_t nsrow = last - first;
  return z_.values[z_.value_begin[t] + (b - z_.first_column[t]) * nsrow + (it - first)];
}

}  // namespace dba
