// Sparse Cholesky of the damped RCS; see sparse_cholesky.h.
#include "dba/common/blas_threads.h"
#include "dba/solver/sparse_cholesky.h"

#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>


#ifdef DBA_HAVE_CHOLMOD
#include "dba/solver/cholmod_library.h"
#else
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#endif

namespace dba {
namespace {

// S's upper triangle in compressed sparse columns read as rows: column r of
// the CSC holds row r of the upper triangle, i.e. the CSC of the lower
// triangle of the symmetric S. 32-bit indices (a factor that large would not
// fit this memory anyway; refused below).
struct UpperPattern {
  std::vector<int> col_ptr;  // n + 1
  std::vector<int> row_idx;  // nnz
};

UpperPattern BuildUpperPattern(const BsmcMatrix& S) {
  UpperPattern p;
  const int64_t n = S.num_rows();
  int64_t nnz = 0;
  for (int32_t i = 0; i < S.num_block_rows(); ++i) {
    const int ci = S.block_size(i);
    int64_t row_width = 0;  // scalars right of the diagonal block
    for (int64_t blk = S.row_begin(i) + 1; blk < S.row_end(i); ++blk) {
      row_width += S.block_size(S.block_col(blk));
    }
    nnz += ci * row_width + int64_t{ci} * (ci + 1) / 2;
  }
  if (n >= std::numeric_limits<int>::max() || nnz >= std::numeric_limits<int>::max()) {
    throw std::runtime_error("sparse Cholesky: the RCS has " + std::to_string(nnz) +
                             " scalar non-zeros, more than 32-bit indices hold; use "
                             "--linear-solver pcg");
  }
  p.col_ptr.resize(n + 1);
  p.row_idx.resize(nnz);
  int64_t k = 0;
  for (int32_t i = 0; i < S.num_block_rows(); ++i) {
    const int ci = S.block_size(i);
    const int64_t oi = S.scalar_offset(i);
    for (int a = 0; a < ci; ++a) {
      p.col_ptr[oi + a] = static_cast<int>(k);
      for (int64_t blk = S.row_begin(i); blk < S.row_end(i); ++blk) {
        const int32_t j = S.block_col(blk);
        const int64_t oj = S.scalar_offset(j);
        for (int c = (j == i ? a : 0); c < S.block_size(j); ++c) {
          p.row_idx[k++] = static_cast<int>(oj + c);
        }
      }
    }
  }
  p.col_ptr[n] = static_cast<int>(k);
  return p;
}

// Gathers S's values into the pattern's order.
void FillUpperValues(const BsmcMatrix& S, const UpperPattern& p, double* values) {
  const int32_t nb = S.num_block_rows();
#pragma omp parallel for schedule(static) if (nb > 1024)
  for (int32_t i = 0; i < nb; ++i) {
    const int ci = S.block_size(i);
    const int64_t oi = S.scalar_offset(i);
    for (int a = 0; a < ci; ++a) {
      int64_t k = p.col_ptr[oi + a];
      for (int64_t blk = S.row_begin(i); blk < S.row_end(i); ++blk) {
        const int cj = S.block_size(S.block_col(blk));
        const double* row = S.block_values(blk) + int64_t{a} * cj;
        for (int c = (S.block_col(blk) == i ? a : 0); c < cj; ++c) values[k++] = row[c];
      }
    }
  }
}

// The rows (and columns) flagged in `identity` made the identity's.
void PinToIdentity(const std::vector<uint8_t>& identity, const UpperPattern& p, double* values) {
  if (identity.empty()) return;
  const int64_t n = static_cast<int64_t>(p.col_ptr.size()) - 1;
  for (int64_t c = 0; c < n; ++c) {
    for (int k = p.col_ptr[c]; k < p.col_ptr[c + 1]; ++k) {
      const int r = p.row_idx[k];
      if (identity[r] || identity[c]) values[k] = r == c ? 1.0 : 0.0;
    }
  }
}

}  // namespace

bool SparseCholeskySolver::FactorizeWithIdentityRows(const BsmcMatrix& S, std::vector<uint8_t> rows) {
  identity_rows_ = std::move(rows);
  const bool ok = Factorize(S);
  identity_rows_.clear();
  return ok;
}

#ifdef DBA_HAVE_CHOLMOD

namespace {

// Below this many flops per factorization CHOLMOD runs on one BLAS thread
// (bench/README.md, "Linear solvers": BLAS threads).
constexpr double kThreadedBlasMinFlops = 1e10;

struct CholmodSession {
  cholmod_common c;
  CholmodSession() {
    Cholmod().cholmod_start(&c);
    c.print = 0;  // errors are reported by the caller
    c.nmethods = 1;
  }
  ~CholmodSession() { Cholmod().cholmod_finish(&c); }
  CholmodSession(const CholmodSession&) = delete;
  CholmodSession& operator=(const CholmodSession&) = delete;
};

// The block graph of S (pattern only, lower triangle as CSC), analysed with
// AMD: block order and the simplicial column counts.
struct BlockAnalysis {
  std::vector<int> perm;       // block order
  std::vector<double> col_count;  // nnz (in blocks) of each column of L, in order
};

BlockAnalysis AnalyseBlockGraph(const BsmcMatrix& S, BlockOrdering ordering = BlockOrdering::kAmd) {
  CholmodSession cm;
  const int nb = S.num_block_rows();
  cholmod_sparse* A = Cholmod().cholmod_allocate_sparse(nb, nb, S.num_blocks(), 1, 1, -1, CHOLMOD_PATTERN, &cm.c);
  if (A == nullptr) throw std::runtime_error("sparse Cholesky: out of memory (block graph)");
  int* ap = static_cast<int*>(A->p);
  int* ai = static_cast<int*>(A->i);
  for (int i = 0; i <= nb; ++i) ap[i] = static_cast<int>(i < nb ? S.row_begin(i) : S.num_blocks());
  for (int64_t b = 0; b < S.num_blocks(); ++b) ai[b] = S.block_col(b);
  cm.c.method[0].ordering = ordering == BlockOrdering::kNestedDissection ? CHOLMOD_METIS : CHOLMOD_AMD;
  cm.c.supernodal = CHOLMOD_SIMPLICIAL;
  cholmod_factor* L = Cholmod().cholmod_analyze(A, &cm.c);
  Cholmod().cholmod_free_sparse(&A, &cm.c);
  if (L == nullptr) throw std::runtime_error("sparse Cholesky: block analysis failed");
  BlockAnalysis out;
  out.perm.assign(static_cast<int*>(L->Perm), static_cast<int*>(L->Perm) + nb);
  out.col_count.resize(nb);
  for (int k = 0; k < nb; ++k) out.col_count[k] = static_cast<int*>(L->ColCount)[k];
  Cholmod().cholmod_free_factor(&L, &cm.c);
  return out;
}

}  // namespace

SparseFactorEstimate EstimateSparseFactor(const BsmcMatrix& S) {
  SparseFactorEstimate e;
  e.available = true;
  const BlockAnalysis a = AnalyseBlockGraph(S);
  // Column k of the block factor: count_k blocks of the mean size c; its
  // scalar columns hold c·count_k values (a supernode stores its diagonal
  // block whole), and its elimination costs about (c·count_k)² flops per
  // scalar column. Supernode amalgamation adds explicit zeros on top: the
  // analysis of the scalar matrix gives the exact size (factor_values()).
  const double c = static_cast<double>(S.num_rows()) / std::max(1, S.num_block_rows());
  for (double count : a.col_count) {
    e.factor_values += c * c * count;
    e.flops += c * (c * count) * (c * count);
  }
  return e;
}

struct SparseCholeskySolver::Impl {
  CholmodSession cm;
  UpperPattern pattern;
  cholmod_sparse* A = nullptr;
  cholmod_factor* L = nullptr;
  cholmod_dense *B = nullptr, *X = nullptr, *Y = nullptr, *E = nullptr;
  ~Impl() {
    Cholmod().cholmod_free_dense(&B, &cm.c);
    Cholmod().cholmod_free_dense(&X, &cm.c);
    Cholmod().cholmod_free_dense(&Y, &cm.c);
    Cholmod().cholmod_free_dense(&E, &cm.c);
    Cholmod().cholmod_free_factor(&L, &cm.c);
    if (A != nullptr) {
      // The index arrays belong to `pattern`: detach them before freeing.
      A->p = nullptr;
      A->i = nullptr;
      Cholmod().cholmod_free_sparse(&A, &cm.c);
    }
  }
};

SparseCholeskySolver::SparseCholeskySolver(const BsmcMatrix& S, int blas_threads, BlockOrdering ordering)
    : impl_(std::make_unique<Impl>()), blas_threads_(blas_threads) {
  Impl& m = *impl_;
  const BlockAnalysis blocks = AnalyseBlockGraph(S, ordering);
  std::vector<int> perm;
  perm.reserve(S.num_rows());
  for (int b : blocks.perm) {
    for (int a = 0; a < S.block_size(b); ++a) perm.push_back(static_cast<int>(S.scalar_offset(b) + a));
  }
  m.pattern = BuildUpperPattern(S);
  const int n = static_cast<int>(S.num_rows());
  const size_t nnz = m.pattern.row_idx.size();
  // A CSC over the pattern's arrays; values allocated by CHOLMOD.
  m.A = static_cast<cholmod_sparse*>(Cholmod().cholmod_malloc(1, sizeof(cholmod_sparse), &m.cm.c));
  if (m.A == nullptr) throw std::runtime_error("sparse Cholesky: out of memory");
  *m.A = cholmod_sparse{};
  m.A->nrow = n;
  m.A->ncol = n;
  m.A->nzmax = nnz;
  m.A->p = m.pattern.col_ptr.data();
  m.A->i = m.pattern.row_idx.data();
  m.A->x = Cholmod().cholmod_malloc(nnz, sizeof(double), &m.cm.c);
  m.A->stype = -1;  // lower triangle of S = upper triangle read by rows
  m.A->itype = CHOLMOD_INT;
  m.A->xtype = CHOLMOD_REAL;
  m.A->dtype = CHOLMOD_DOUBLE;
  m.A->sorted = 1;
  m.A->packed = 1;
  if (m.A->x == nullptr) throw std::runtime_error("sparse Cholesky: out of memory");
  m.cm.c.method[0].ordering = CHOLMOD_GIVEN;
  m.cm.c.postorder = 1;
  m.cm.c.supernodal = CHOLMOD_SUPERNODAL;
  m.L = Cholmod().cholmod_analyze_p(m.A, perm.data(), nullptr, 0, &m.cm.c);
  if (m.L == nullptr || m.cm.c.status < 0) {
    throw std::runtime_error("sparse Cholesky: analysis failed (CHOLMOD status " +
                             std::to_string(m.cm.c.status) + ")");
  }
  m.B = Cholmod().cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &m.cm.c);
  if (m.B == nullptr) throw std::runtime_error("sparse Cholesky: out of memory");
  // A small factor is many short BLAS calls, each a barrier for BLAS's
  // threads: one thread is as fast there, and on a loaded machine far faster.
  if (m.cm.c.fl < kThreadedBlasMinFlops) blas_threads_ = 1;
}

SparseCholeskySolver::~SparseCholeskySolver() = default;

double SparseCholeskySolver::factor_values() const {
  const cholmod_factor* L = impl_->L;
  return L->is_super ? static_cast<double>(L->xsize) : impl_->cm.c.lnz;
}

int64_t SparseCholeskySolver::MemoryBytes() const {
  const Impl& m = *impl_;
  const int64_t nnz = static_cast<int64_t>(m.pattern.row_idx.size());
  const int64_t n = static_cast<int64_t>(m.pattern.col_ptr.size());
  return static_cast<int64_t>(factor_values() * 8.0) + nnz * 12 + n * 4 * 8;
}

bool SparseCholeskySolver::Factorize(const BsmcMatrix& S) {
  Impl& m = *impl_;
  FillUpperValues(S, m.pattern, static_cast<double*>(m.A->x));
  PinToIdentity(identity_rows_, m.pattern, static_cast<double*>(m.A->x));
  const BlasThreads blas(blas_threads_);
  const int ok = Cholmod().cholmod_factorize(m.A, m.L, &m.cm.c);
  if (m.cm.c.status == CHOLMOD_NOT_POSDEF) {
    const int64_t minor = static_cast<int64_t>(m.L->minor);
    failed_row_ = minor < static_cast<int64_t>(m.L->n) ? static_cast<const int*>(m.L->Perm)[minor] : -1;
    return false;
  }
  if (!ok || m.cm.c.status < 0) {
    throw std::runtime_error("sparse Cholesky: factorization failed (CHOLMOD status " +
                             std::to_string(m.cm.c.status) + ")");
  }
  return true;
}

void SparseCholeskySolver::SolveFactored(const double* b, double* x) {
  Impl& m = *impl_;
  const int64_t n = static_cast<int64_t>(m.B->nrow);
  std::copy(b, b + n, static_cast<double*>(m.B->x));
  const BlasThreads blas(blas_threads_);
  if (!Cholmod().cholmod_solve2(CHOLMOD_A, m.L, m.B, nullptr, &m.X, nullptr, &m.Y, &m.E, &m.cm.c)) {
    throw std::runtime_error("sparse Cholesky: solve failed (CHOLMOD status " +
                             std::to_string(m.cm.c.status) + ")");
  }
  const double* solution = static_cast<const double*>(m.X->x);
  std::copy(solution, solution + n, x);
}

void SparseCholeskySolver::SolveFactoredColumns(const double* B, int columns, double* X) {
  Impl& m = *impl_;
  const int64_t n = static_cast<int64_t>(m.B->nrow);
  cholmod_dense* b = Cholmod().cholmod_allocate_dense(n, columns, n, CHOLMOD_REAL, &m.cm.c);
  if (b == nullptr) throw std::runtime_error("sparse Cholesky: out of memory");
  std::copy(B, B + n * columns, static_cast<double*>(b->x));
  cholmod_dense *x = nullptr, *y = nullptr, *e = nullptr;
  const BlasThreads blas(blas_threads_);
  const int ok = Cholmod().cholmod_solve2(CHOLMOD_A, m.L, b, nullptr, &x, nullptr, &y, &e, &m.cm.c);
  if (ok) std::copy(static_cast<const double*>(x->x), static_cast<const double*>(x->x) + n * columns, X);
  for (cholmod_dense* d : {b, x, y, e}) Cholmod().cholmod_free_dense(&d, &m.cm.c);
  if (!ok) {
    throw std::runtime_error("sparse Cholesky: solve failed (CHOLMOD status " + std::to_string(m.cm.c.status) + ")");
  }
}

SupernodalFactor SparseCholeskySolver::TakeFactor() {
  Impl& m = *impl_;
  const cholmod_factor& L = *m.L;
  if (!L.is_super || L.itype != CHOLMOD_INT) {
    throw std::logic_error("sparse Cholesky: the factor is not supernodal with int indices");
  }
  const int64_t n = static_cast<int64_t>(L.n), ns = static_cast<int64_t>(L.nsuper);
  const auto copy = [](const void* from, int64_t count) {
    const int* p = static_cast<const int*>(from);
    return std::vector<int64_t>(p, p + count);
  };
  SupernodalFactor f;
  f.perm = copy(L.Perm, n);
  f.first_column = copy(L.super, ns + 1);
  f.row_begin = copy(L.pi, ns + 1);
  f.rows = copy(L.s, f.row_begin[ns]);
  f.value_begin = copy(L.px, ns + 1);
  // The factor's values stay where CHOLMOD put them, with the factor and
  // its session (the solver no longer holds it); S's copy and the solve's
  // vectors go now.
  Cholmod().cholmod_free_dense(&m.B, &m.cm.c);
  Cholmod().cholmod_free_dense(&m.X, &m.cm.c);
  Cholmod().cholmod_free_dense(&m.Y, &m.cm.c);
  Cholmod().cholmod_free_dense(&m.E, &m.cm.c);
  m.A->p = nullptr;
  m.A->i = nullptr;
  Cholmod().cholmod_free_sparse(&m.A, &m.cm.c);
  m.pattern = UpperPattern{};
  struct Held {
    std::unique_ptr<Impl> impl;
    ~Held() { impl.reset(); }
  };
  f.values = std::span<double>(static_cast<double*>(L.x), f.value_begin[ns]);
  auto held = std::make_shared<Held>();
  held->impl = std::move(impl_);
  f.storage = std::move(held);
  CheckFactorLayout(f);
  return f;
}

#else  // Eigen's simplicial Cholesky: no GPL code in the build.

SparseFactorEstimate EstimateSparseFactor(const BsmcMatrix&) { return {}; }

struct SparseCholeskySolver::Impl {
  UpperPattern pattern;
  std::vector<double> values;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> llt;
};

SparseCholeskySolver::SparseCholeskySolver(const BsmcMatrix& S, int blas_threads, BlockOrdering)
    : impl_(std::make_unique<Impl>()), blas_threads_(blas_threads) {
  impl_->pattern = BuildUpperPattern(S);
  impl_->values.assign(impl_->pattern.row_idx.size(), 0.0);
  const int n = static_cast<int>(S.num_rows());
  const Eigen::Map<const Eigen::SparseMatrix<double>> A(
      n, n, static_cast<int>(impl_->values.size()), impl_->pattern.col_ptr.data(),
      impl_->pattern.row_idx.data(), impl_->values.data());
  impl_->llt.analyzePattern(A);
}

SparseCholeskySolver::~SparseCholeskySolver() = default;

double SparseCholeskySolver::factor_values() const { return -1.0; }

int64_t SparseCholeskySolver::MemoryBytes() const {
  const int64_t nnz = static_cast<int64_t>(impl_->pattern.row_idx.size());
  return nnz * 12 + static_cast<int64_t>(impl_->llt.matrixL().nestedExpression().nonZeros()) * 12;
}

bool SparseCholeskySolver::Factorize(const BsmcMatrix& S) {
  Impl& m = *impl_;
  const int n = static_cast<int>(S.num_rows());
  FillUpperValues(S, m.pattern, m.values.data());
  PinToIdentity(identity_rows_, m.pattern, m.values.data());
  const Eigen::Map<const Eigen::SparseMatrix<double>> A(
      n, n, static_cast<int>(m.values.size()), m.pattern.col_ptr.data(), m.pattern.row_idx.data(),
      m.values.data());
  m.llt.factorize(A);
  return m.llt.info() == Eigen::Success;
}

void SparseCholeskySolver::SolveFactored(const double* b, double* x) {
  const int64_t n = static_cast<int64_t>(impl_->pattern.col_ptr.size()) - 1;
  const Eigen::VectorXd rhs = Eigen::Map<const Eigen::VectorXd>(b, n);
  Eigen::Map<Eigen::VectorXd>(x, n) = impl_->llt.solve(rhs);
}


void SparseCholeskySolver::SolveFactoredColumns(const double* B, int columns, double* X) {
  const int64_t n = static_cast<int64_t>(impl_->pattern.col_ptr.size()) - 1;
  const Eigen::MatrixXd rhs = Eigen::Map<const Eigen::MatrixXd>(B, n, columns);
  Eigen::Map<Eigen::MatrixXd>(X, n, columns) = impl_->llt.solve(rhs);
}

SupernodalFactor SparseCholeskySolver::TakeFactor() {
  const Eigen::SparseMatrix<double>& L = impl_->llt.matrixL().nestedExpression();
  const int64_t n = L.cols();
  SupernodalFactor f;  // a supernode per column
  f.perm.resize(n);
  const auto& position = impl_->llt.permutationP().indices();
  for (int64_t i = 0; i < n; ++i) f.perm[position[i]] = i;
  f.first_column.resize(n + 1);
  for (int64_t j = 0; j <= n; ++j) f.first_column[j] = j;
  f.row_begin.assign(L.outerIndexPtr(), L.outerIndexPtr() + n + 1);
  f.value_begin = f.row_begin;
  f.rows.assign(L.innerIndexPtr(), L.innerIndexPtr() + L.nonZeros());
  SetFactorValues(std::vector<double>(L.valuePtr(), L.valuePtr() + L.nonZeros()), &f);
  CheckFactorLayout(f);
  return f;
}

#endif

}  // namespace dba
