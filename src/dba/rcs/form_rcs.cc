// Point-by-point RCS formation (paper eq. 4); see form_rcs.h.
#include "dba/rcs/form_rcs.h"

#include "dba/common/progress.h"

#include <omp.h>

#include <sys/mman.h>

#include <algorithm>
#include <cmath>
#include <new>
#include <utility>

#include "dba/common/check.h"
#include "dba/common/striped_locks.h"
#include "dba/rcs/rcs_pattern.h"

namespace dba {
namespace {

// block(rows x n, row-major, in S) += m.leftCols(n): the intrinsics blocks
// keep only their free columns.
template <int kRows, typename M>
void AddLeftCols(double* block, int n, const M& m) {
  if (n == M::ColsAtCompileTime) {
    Eigen::Map<Eigen::Matrix<double, kRows, M::ColsAtCompileTime, Eigen::RowMajor>>(block) += m;
  } else {
    Eigen::Map<Eigen::Matrix<double, kRows, Eigen::Dynamic, Eigen::RowMajor>>(block, kRows, n) +=
        m.leftCols(n);
  }
}

// block (kC x kC, row-major, in S) += Aᵀ M B for A, B 2 x kC (row-major)
// and M 2x2 (row-major): the rank-2 update J_c,aᵀ M_ab J_c,b of eq. 4
// (eliminate_point.h), 2 kC² + 4 kC flops. N = M B first (4 kC flops), then
// row x is two fused multiply-adds over N's contiguous rows with A's column
// x as coefficients, read straight from memory as broadcasts: no
// arithmetic between a row's coefficients and its update. (Forming the
// coefficients (Aᵀ M)_x per row instead cost 4 scalar flops and two
// register shuffles per row; Eigen's lazyProduct of the expression compiled
// to scalar code, 60% of a 2,500-image survey's solve.)
template <int kC>
inline void AddRank2(double* __restrict block, const double* __restrict A,
                     const double (&M)[4], const double* __restrict B) {
  double N[2 * kC];
#pragma omp simd
  for (int y = 0; y < kC; ++y) {
    N[y] = M[0] * B[y] + M[1] * B[kC + y];
    N[kC + y] = M[2] * B[y] + M[3] * B[kC + y];
  }
  for (int x = 0; x < kC; ++x) {
    const double a0 = A[x], a1 = A[kC + x];
    double* __restrict row = block + x * kC;
#pragma omp simd
    for (int y = 0; y < kC; ++y) row[y] = (row[y] + a0 * N[y]) + a1 * N[kC + y];
  }
}

// The observations of one point that share an intrinsics row g, summed:
//   Σ_a W_i,a,  Σ_a J_i,aᵀ J_i,a,  Σ_a J_i,aᵀ r_a.
// Every intrinsics block of the point's sub-RCS is a product of these sums
// (T_i,a = W_i,a V_λ⁻¹ and V_λ⁻¹ is the point's): S(g, h) -= (Σ_g W) V_λ⁻¹
// (Σ_h W)ᵀ. With G groups among a point's m observations that costs
// O(m G + G²) instead of O(m²): a large saving for shared intrinsics (G is 1
// or 2), none for one group per image (G = m).
template <int kI>
struct GroupSums {
  int32_t row = -1;
  Eigen::Matrix<double, kI, 3> W;
  Eigen::Matrix<double, kI, kI> JtJ;
  Eigen::Matrix<double, kI, 1> g;
};

template <class Model>
void SumByGroup(const PointSystem<Model>& p,
                std::vector<GroupSums<PointSystem<Model>::kI>>* groups) {
  groups->clear();
  for (int a = 0; a < p.num_obs; ++a) {
    const int32_t row = p.intrinsics_row[a];
    if (row < 0) continue;
    auto it = std::find_if(groups->begin(), groups->end(),
                           [row](const auto& s) { return s.row == row; });
    if (it == groups->end()) {
      groups->push_back({row, p.W_i[a], p.J_i[a].transpose() * p.J_i[a],
                         p.J_i[a].transpose() * p.r[a]});
    } else {
      it->W += p.W_i[a];
      it->JtJ.noalias() += p.J_i[a].transpose() * p.J_i[a];
      it->g.noalias() += p.J_i[a].transpose() * p.r[a];
    }
  }
  std::sort(groups->begin(), groups->end(),
            [](const auto& x, const auto& y) { return x.row < y.row; });
}

// Zeroed doubles in fresh pages of their own (an anonymous mapping), which
// take memory only where they are written: a thread's sums of the seam rows
// hold about the rows at its own range's two ends, not all of them.
class ZeroPages {
 public:
  ZeroPages() = default;
  explicit ZeroPages(int64_t n) : bytes_(static_cast<size_t>(std::max<int64_t>(n, 1)) * sizeof(double)) {
    void* p = ::mmap(nullptr, bytes_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE,
                     -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    p_ = static_cast<double*>(p);
  }
  ZeroPages(ZeroPages&& o) noexcept : p_(std::exchange(o.p_, nullptr)), bytes_(o.bytes_) {}
  ZeroPages& operator=(ZeroPages&& o) noexcept {
    std::swap(p_, o.p_);
    std::swap(bytes_, o.bytes_);
    return *this;
  }
  ~ZeroPages() {
    if (p_ != nullptr) ::munmap(p_, bytes_);
  }
  double* data() const { return p_; }

 private:
  double* p_ = nullptr;
  size_t bytes_ = 0;
};

// The rows of S that more than one thread's points touch, laid out back to
// back for a thread's own sums of them: per such row its values (as in S),
// then its b, gradient and diagonal.
struct SeamLayout {
  std::vector<int32_t> slot;  // per row of S: its place among the seam rows, or -1
  std::vector<int32_t> rows;  // the seam rows, increasing
  std::vector<int64_t> start; // per seam row: where its values begin (then 3 vectors)
  int64_t doubles = 0;
};

}  // namespace

// The later threads' sums of the shared rows, and their layout.
struct FormationSeams {
  SeamLayout layout;
  std::vector<ZeroPages> sums;  // thread t > 0: sums[t - 1]
};

namespace {

SeamLayout LayOutSeams(const BsmcMatrix& S, const std::vector<uint8_t>& shared_rows) {
  SeamLayout seams;
  seams.slot.assign(S.num_block_rows(), -1);
  for (int32_t r = 0; r < S.num_block_rows(); ++r) {
    if (!shared_rows[r]) continue;
    seams.slot[r] = static_cast<int32_t>(seams.rows.size());
    seams.rows.push_back(r);
    seams.start.push_back(seams.doubles);
    seams.doubles += S.value_offset(S.row_end(r)) - S.value_offset(S.row_begin(r)) +
                     3 * int64_t{S.block_size(r)};
  }
  return seams;
}

// Where a thread adds its points: the system's own arrays, or the thread's
// private copy of them (no locks; summed afterwards). Rows that other
// threads also write: the thread's own sums of them (a thread after the
// first, `seam`; summed in thread order afterwards), or under the row locks.
struct RcsTarget {
  double* values;        // S's values (BSMC layout)
  double* b;
  double* gradient;      // camera_side_gradient
  double* jtj_diagonal;  // camera_side_jtj_diagonal
  StripedLocks* locks;   // null: no locking
  // With locks: the rows that other threads also write (null: all).
  const uint8_t* shared_rows = nullptr;
  const SeamLayout* seams = nullptr;  // with `seam`: its layout
  double* seam = nullptr;
  bool Locks(int64_t row) const {
    return locks != nullptr && (shared_rows == nullptr || shared_rows[row] != 0);
  }
  void Lock(int64_t row) const {
    if (Locks(row)) locks->Lock(row);
  }
  void Unlock(int64_t row) const {
    if (Locks(row)) locks->Unlock(row);
  }
  // Where row `row` is written: block b's values at
  // values + S.value_offset(b) - shift, and its b, gradient and diagonal.
  struct Row {
    double* values;
    int64_t shift;
    double* b;
    double* gradient;
    double* diagonal;
  };
  Row Place(const BsmcMatrix& S, int32_t row) const {
    const int32_t s = seam != nullptr ? seams->slot[row] : -1;
    if (s < 0) {
      const int64_t o = S.scalar_offset(row);
      return {values, 0, b + o, gradient + o, jtj_diagonal + o};
    }
    const int64_t first = S.value_offset(S.row_begin(row));
    double* v = seam + seams->start[s];
    double* vectors = v + (S.value_offset(S.row_end(row)) - first);
    const int64_t size = S.block_size(row);
    return {v, first, vectors, vectors + size, vectors + 2 * size};
  }
};

// Adds point k's sub-RCS and rhs into the system, row by row under the row
// locks. For observation a with camera row c_a, and the point's intrinsics
// rows g with their sums (GroupSums), K_a = J_p,a V_λ⁻¹:
//   row c_a: S(c_a, c_b) += J_c,aᵀ M_ab J_c,b for c_b >= c_a, with
//            M_ab = [a == b] I - K_a J_p,bᵀ (the own J_c,aᵀ J_c,a included);
//            S(c_a, g) += J_c,aᵀ ([g == g_a] J_i,a - K_a (Σ_g W)ᵀ) for every g;
//   row g:   S(g, h) -= (Σ_g W) V_λ⁻¹ (Σ_h W)ᵀ for h >= g, plus Σ_g J_iᵀ J_i.
// A camera row repeated within the point (a camera seeing it twice) gets
// both M_ab and M_ba terms on its diagonal block, as the dense product
// does. Intrinsic rows come after camera rows, so every block written is in
// the upper triangle.
// Per-thread scratch of AddPointToRcs.
template <class Model>
struct AddScratch {
  std::vector<GroupSums<PointSystem<Model>::kI>> groups;
  std::vector<int> order;  // the point's observations by camera row
};

// The observations of p in increasing camera row (fixed cameras, row -1,
// first): an insertion sort, linear when the input lists a point's
// observations by camera already (BAL files do).
template <class Model>
void SortByCameraRow(const PointSystem<Model>& p, std::vector<int>* order) {
  order->resize(p.num_obs);
  int* o = order->data();
  for (int a = 0; a < p.num_obs; ++a) {
    const int32_t row = p.camera_row[a];
    int x = a;
    for (; x > 0 && p.camera_row[o[x - 1]] > row; --x) o[x] = o[x - 1];
    o[x] = a;
  }
}

template <class Model>
void AddPointToRcs(const PointSystem<Model>& p, AddScratch<Model>& scratch, const BsmcMatrix& S,
                   const RcsTarget& t) {
  constexpr int kC = Model::kCamera;
  constexpr int kI = PointSystem<Model>::kI;
  auto& groups = scratch.groups;
  // The blocks of one row are visited in increasing column (cameras sorted,
  // then the intrinsic rows, which come after every camera row, sorted):
  // each is sought forward from the last instead of searched for anew.
  auto seek = [&](int64_t* position, const RcsTarget::Row& place, int32_t row, int32_t col) {
    const int64_t block = S.SeekBlock(*position, row, col);
    DBA_DCHECK(block >= 0);  // the pattern (rcs_pattern) holds every pair of a point's rows
    *position = block;
    return place.values + (S.value_offset(block) - place.shift);
  };
  if constexpr (Model::kIntrinsics > 0) SumByGroup(p, &groups);
  SortByCameraRow(p, &scratch.order);
  const int* order = scratch.order.data();
  int same_row_begin = 0;  // first of the sorted observations with this row
  for (int x = 0; x < p.num_obs; ++x) {
    const int a = order[x];
    const int32_t ca = p.camera_row[a];
    if (ca < 0) continue;
    if (p.camera_row[order[same_row_begin]] != ca) same_row_begin = x;
    const Eigen::Matrix<double, kC, 1> g_c = p.J_c[a].transpose() * p.r[a];
    const PointJacobian& K = p.K[a];
    t.Lock(ca);
    const RcsTarget::Row place = t.Place(S, ca);
    int64_t position = S.diagonal_block(ca);
    // Every b with cb >= ca; a camera seeing the point twice gets both
    // M_ab and M_ba on its diagonal block.
    for (int y = same_row_begin; y < p.num_obs; ++y) {
      const int b = order[y];
      const double* k0 = K.data();  // K's rows, and J_p,b's
      const double* k1 = k0 + 3;
      const double* q0 = p.J_p[b].data();
      const double* q1 = q0 + 3;
      const double diagonal = b == a ? 1.0 : 0.0;
      const double M[4] = {diagonal - (k0[0] * q0[0] + k0[1] * q0[1] + k0[2] * q0[2]),
                           -(k0[0] * q1[0] + k0[1] * q1[1] + k0[2] * q1[2]),
                           -(k1[0] * q0[0] + k1[1] * q0[1] + k1[2] * q0[2]),
                           diagonal - (k1[0] * q1[0] + k1[1] * q1[1] + k1[2] * q1[2])};
      AddRank2<kC>(seek(&position, place, ca, p.camera_row[b]), p.J_c[a].data(), M, p.J_c[b].data());
    }
    if constexpr (Model::kIntrinsics > 0) {
      for (const auto& gs : groups) {
        typename PointSystem<Model>::IntrinsicsJac Z = -K * gs.W.transpose();
        if (gs.row == p.intrinsics_row[a]) Z += p.J_i[a];
        const Eigen::Matrix<double, kC, kI> m = p.J_c[a].transpose() * Z;
        AddLeftCols<kC>(seek(&position, place, ca, gs.row), S.block_size(gs.row), m);
      }
    }
    Eigen::Map<Eigen::Matrix<double, kC, 1>>(place.b) -= p.J_c[a].transpose() * (p.r[a] - K * p.g_p);
    Eigen::Map<Eigen::Matrix<double, kC, 1>>(place.gradient) += g_c;
    Eigen::Map<Eigen::Matrix<double, kC, 1>>(place.diagonal) +=
        p.J_c[a].colwise().squaredNorm().transpose();
    t.Unlock(ca);
  }
  if constexpr (Model::kIntrinsics > 0) {
    for (size_t x = 0; x < groups.size(); ++x) {
      const int32_t gx = groups[x].row;
      const int nx = S.block_size(gx);
      const Eigen::Matrix<double, kI, 3> T = groups[x].W * p.V_inv;
      const Eigen::Matrix<double, kI, 1> rhs = -groups[x].g + T * p.g_p;
      t.Lock(gx);
      const RcsTarget::Row place = t.Place(S, gx);
      int64_t position = S.diagonal_block(gx);
      for (size_t y = x; y < groups.size(); ++y) {
        const int32_t gy = groups[y].row;
        Eigen::Matrix<double, kI, kI> m = -T.lazyProduct(groups[y].W.transpose());
        if (y == x) m += groups[x].JtJ;
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            seek(&position, place, gx, gy), nx, S.block_size(gy)) +=
            m.topLeftCorner(nx, S.block_size(gy));
      }
      for (int d = 0; d < nx; ++d) {
        place.b[d] += rhs[d];
        place.gradient[d] += groups[x].g[d];
        place.diagonal[d] += groups[x].JtJ(d, d);
      }
      t.Unlock(gx);
    }
  }
}

// Private accumulation (one copy of S, b and the gradients per thread but
// the first, summed in thread order afterwards) while the copies take at
// most this many bytes: no locks, and a sum whose order does not depend on
// scheduling. Small RCSs gain most: every point of a 49-camera problem
// touches the same few rows, so two threads under row locks mostly wait.
constexpr int64_t kPrivateCopyBytes = 32 << 20;

}  // namespace

int64_t FormationCopyBytes(int64_t values, int64_t rows, int num_threads) {
  const int64_t bytes = int64_t{num_threads - 1} * (values + 3 * rows) * 8;
  return num_threads > 1 && bytes <= kPrivateCopyBytes ? bytes : 0;
}

int64_t FormationSeamBytesLimit(int64_t values, int64_t rows, int num_threads) {
  if (num_threads <= 1 || FormationCopyBytes(values, rows, num_threads) > 0) return 0;
  return (values + 3 * rows) * 8 / 8;
}

namespace {

// Thread t of `threads` forms the points [n t / threads, n (t + 1) / threads).
int64_t RangeBegin(int64_t n, int t, int threads) { return n * t / threads; }

// The rows of S that points of more than one thread's range touch: only
// those need a lock (neighbouring points see the same cameras, so at most
// the cameras near the ranges' seams, and the shared intrinsics rows). The
// lock's exchange was a tenth of formation's own time on the 100K-image
// survey. Kept for the next formation of the same problem; recomputed when
// the number of threads or of observations changes (a system is formed for
// one problem's pattern: dropping observations means a new system, and the
// count is a guard).
void FindSharedRows(const Problem& problem, const UnknownLayout& layout, int threads,
                    RcsSystem* sys) {
  const int32_t rows = layout.num_block_rows();
  // Per row, the first thread that touches it, or `kShared`.
  constexpr int kShared = -2;
  std::vector<int> toucher(rows, -1);
  const int64_t n = problem.num_points();
  for (int t = 0; t < threads; ++t) {
    const int64_t first = problem.point_offsets[RangeBegin(n, t, threads)];
    const int64_t last = problem.point_offsets[RangeBegin(n, t + 1, threads)];
    auto touch = [&](int32_t row) {
      if (row < 0) return;
      int& who = toucher[row];
      who = who == -1 || who == t ? t : kShared;
    };
    for (int64_t o = first; o < last; ++o) {
      const auto touched = layout.rows_of_image(problem, problem.obs_camera[o]);
      touch(touched.camera);
      touch(touched.intrinsics);
    }
  }
  sys->shared_rows.assign(rows, 0);
  for (int32_t r = 0; r < rows; ++r) sys->shared_rows[r] = toucher[r] == kShared;
  sys->shared_rows_threads = threads;
  sys->shared_rows_observations = problem.num_observations();
  sys->seams.reset();  // laid out again for these rows
  // What the later threads' own sums of the shared rows hold: each the rows
  // its points touch (their values and 3 vectors).
  const BsmcMatrix& S = sys->S;
  sys->shared_rows_later_doubles = 0;
  std::vector<int> seen(rows, -1);
  for (int t = 1; t < threads; ++t) {
    const int64_t first = problem.point_offsets[RangeBegin(n, t, threads)];
    const int64_t last = problem.point_offsets[RangeBegin(n, t + 1, threads)];
    for (int64_t o = first; o < last; ++o) {
      const auto touched = layout.rows_of_image(problem, problem.obs_camera[o]);
      for (const int32_t r : {touched.camera, touched.intrinsics}) {
        if (r < 0 || !sys->shared_rows[r] || seen[r] == t) continue;
        seen[r] = t;
        sys->shared_rows_later_doubles += S.value_offset(S.row_end(r)) -
                                          S.value_offset(S.row_begin(r)) + 3 * int64_t{S.block_size(r)};
      }
    }
  }
}

// Whether sys.shared_rows were found for `threads` ranges of this problem.
bool SharedRowsFit(const RcsSystem& sys, int threads, const Problem& problem) {
  return sys.shared_rows_threads == threads &&
         sys.shared_rows_observations == problem.num_observations();
}

// Thread `thread` of `threads`: its slice of the private copies (values,
// then b, gradient and diagonal back to back) added into the system, the
// copies in thread order.
void SumPrivateCopies(const std::vector<std::vector<double>>& copies, int thread, int threads,
                      RcsSystem* sys) {
  const int64_t values = sys->S.num_values(), rows = sys->S.num_rows();
  const std::pair<double*, int64_t> segments[4] = {{sys->S.values().data(), values},
                                                   {sys->b.data(), rows},
                                                   {sys->camera_side_gradient.data(), rows},
                                                   {sys->camera_side_jtj_diagonal.data(), rows}};
  int64_t start = 0;  // of the segment in a copy
  for (const auto& [out, length] : segments) {
    // Slices and copies by the team's size (it may be smaller than asked
    // for: the copies of threads that never ran are empty).
    const int64_t begin = start + length * thread / threads;
    const int64_t end = start + length * (thread + 1) / threads;
    for (int64_t i = begin; i < end; ++i) {
      for (int c = 0; c + 1 < threads; ++c) out[i - start] += copies[c][i];
    }
    start += length;
  }
}

// Thread `thread` of `threads`: its slice of the seam rows, the later
// threads' sums of them added into the system in thread order, and zeroed
// for the next formation where they were written (pages never written stay
// without memory).
void SumSeams(const SeamLayout& seams, const std::vector<ZeroPages>& sums, int thread,
              int threads, RcsSystem* sys) {
  const BsmcMatrix& S = sys->S;
  const int64_t n = static_cast<int64_t>(seams.rows.size());
  for (int64_t i = n * thread / threads; i < n * (thread + 1) / threads; ++i) {
    const int32_t r = seams.rows[i];
    const int64_t first = S.value_offset(S.row_begin(r)), count = S.value_offset(S.row_end(r)) - first;
    const int64_t size = S.block_size(r), o = S.scalar_offset(r);
    double* const out[4] = {sys->S.values().data() + first, sys->b.data() + o,
                            sys->camera_side_gradient.data() + o,
                            sys->camera_side_jtj_diagonal.data() + o};
    const int64_t length[4] = {count, size, size, size};
    for (const ZeroPages& sum : sums) {
      double* in = sum.data() + seams.start[i];
      for (int part = 0; part < 4; ++part) {
        for (int64_t x = 0; x < length[part]; ++x) {
          if (in[x] == 0.0) continue;
          out[part][x] += in[x];
          in[x] = 0.0;
        }
        in += length[part];
      }
    }
  }
}

template <class Model>
void FormRcsWith(const Problem& problem, double lambda, const DampingBounds& bounds,
                 const RobustLoss& loss, int num_threads, RcsSystem* sys) {
  StripedLocks locks;
  double cost = 0.0, max_g_p = 0.0, squared = 0.0, inlier_squared = 0.0, inliers = 0.0;
  const int64_t num_points = problem.num_points();
  const int64_t rows = sys->S.num_rows();
  const int64_t values = sys->S.num_values();
  const bool private_copies = FormationCopyBytes(values, rows, num_threads) > 0;
  if (!private_copies && num_threads > 1 && !SharedRowsFit(*sys, num_threads, problem)) {
    FindSharedRows(problem, sys->layout, num_threads, sys);
  }
  // Thread t > 0 of the private scheme: values, then b, gradient, diagonal.
  std::vector<std::vector<double>> copies(private_copies ? num_threads - 1 : 0);
  // Else the shared rows in each later thread's own sums while they fit
  // (FormationSeamBytesLimit), else under row locks.
  const int64_t limit = FormationSeamBytesLimit(values, rows, num_threads);
  if (limit > 0 && !sys->seams && SharedRowsFit(*sys, num_threads, problem) &&
      sys->shared_rows_later_doubles * 8 <= limit) {
    auto made = std::make_shared<FormationSeams>();
    made->layout = LayOutSeams(sys->S, sys->shared_rows);
    try {  // address space for every thread's layout; pages only where written
      for (int t = 1; t < num_threads; ++t) made->sums.emplace_back(made->layout.doubles);
      sys->seams = std::move(made);
    } catch (const std::bad_alloc&) {  // under a limit on it: the row locks
    }
  }
  const bool use_seams = limit > 0 && sys->seams && SharedRowsFit(*sys, num_threads, problem) &&
                         static_cast<int>(sys->seams->sums.size()) == num_threads - 1;
  static const SeamLayout kNoSeams;
  const SeamLayout& seams = use_seams ? sys->seams->layout : kNoSeams;
  sys->seam_doubles = use_seams ? seams.doubles : 0;
  // The first thread reports its share (RangeBegin: about the first
  // n / threads points).
  ProgressPhase progress("RCS formation");
  const double first_share =
      std::max<double>(1.0, static_cast<double>(RangeBegin(num_points, 1, num_threads)));
#pragma omp parallel num_threads(num_threads) reduction(+ : cost, squared, inlier_squared, inliers) \
    reduction(max : max_g_p)
  {
    PointSystem<Model> p;
    AddScratch<Model> scratch;
    const int thread = omp_get_thread_num();
    const int threads = omp_get_num_threads();
    // Locks on the shared rows alone where they were found for this many
    // threads (the team may be smaller than asked for).
    const uint8_t* shared_rows =
        !private_copies && SharedRowsFit(*sys, threads, problem) ? sys->shared_rows.data() : nullptr;
    // The seams were laid out for a full team's ranges.
    const bool seamed = use_seams && threads == num_threads;
    RcsTarget target{sys->S.values().data(), sys->b.data(), sys->camera_side_gradient.data(),
                     sys->camera_side_jtj_diagonal.data(),
                     private_copies || seamed ? nullptr : &locks, shared_rows};
    if (private_copies && thread > 0) {
      std::vector<double>& c = copies[thread - 1];
      c.assign(values + 3 * rows, 0.0);
      target = {c.data(), c.data() + values, c.data() + values + rows,
                c.data() + values + 2 * rows, nullptr};
    }
    if (seamed && thread > 0) {
      target.seams = &seams;
      target.seam = sys->seams->sums[thread - 1].data();
    }
    // Contiguous ranges of points per thread: neighbouring points see the
    // same cameras, so interleaved chunks would make the threads fight over
    // the same RCS rows (locks and cache lines). Measured on 10M observations
    // (1920 cameras): dynamic chunks of 256 took 6.5 s per formation with 2
    // threads, slower than 2 single-threaded MPI ranks on half the points;
    // contiguous ranges take 3.0 s.
    const int64_t last_point = RangeBegin(num_points, thread + 1, threads);
    for (int64_t k = RangeBegin(num_points, thread, threads); k < last_point; ++k) {
      if (thread == 0 && (k & 4095) == 0) progress.Report(static_cast<double>(k) / first_share);
      LinearizePoint(problem, sys->layout, loss, k, &p);
      EliminatePoint(lambda, bounds, &p);
      AddPointToRcs(p, scratch, sys->S, target);
      cost += p.cost;
      squared += p.residuals.squared;
      inlier_squared += p.residuals.inlier_squared;
      inliers += p.residuals.inliers;
      max_g_p = std::max(max_g_p, p.g_p.cwiseAbs().maxCoeff());
    }
    if (private_copies || seamed) {
      // The copies into the system, each thread a slice, in thread order.
#pragma omp barrier
      if (private_copies) SumPrivateCopies(copies, thread, threads, sys);
      if (seamed) SumSeams(seams, sys->seams->sums, thread, threads, sys);
    }
  }
  sys->cost = cost;
  sys->residuals = {squared, inlier_squared, inliers};
  sys->max_abs_point_gradient = max_g_p;
}

}  // namespace

RcsSystem RcsSystem::ForProblem(const Problem& problem,
                                const std::function<void(const RcsSystem&)>& before_values,
                                bool with_values, bool lever_arm) {
  RcsSystem sys;
  {
    UnknownLayout layout(problem, lever_arm);
    const std::vector<uint64_t> pattern = RcsBlockPattern(problem, layout);
    sys = ForPattern(std::move(layout), pattern, false);
  }
  if (before_values) before_values(sys);
  if (with_values) sys.AllocateValues();
  return sys;
}

RcsSystem RcsSystem::ForPattern(UnknownLayout layout, std::span<const uint64_t> pattern,
                                bool with_values) {
  RcsSystem sys;
  sys.S = BsmcMatrix::BuildStructure(layout.block_sizes(), pattern);
  sys.layout = std::move(layout);
  if (with_values) sys.AllocateValues();
  return sys;
}

void RcsSystem::AllocateValues() {
  S.AllocateValues();
  const int64_t rows = S.num_rows();
  b.assign(rows, 0.0);
  camera_side_gradient.assign(rows, 0.0);
  camera_side_jtj_diagonal.assign(rows, 0.0);
}

void FormRcs(const Problem& problem, double lambda,
             const DampingBounds& bounds, int num_threads, RcsSystem* sys,
             const RobustLoss& loss) {
  sys->S.SetZero();
  std::fill(sys->b.begin(), sys->b.end(), 0.0);
  std::fill(sys->camera_side_gradient.begin(), sys->camera_side_gradient.end(), 0.0);
  std::fill(sys->camera_side_jtj_diagonal.begin(), sys->camera_side_jtj_diagonal.end(), 0.0);
  if (problem.model == CameraModel::kBal) {
    FormRcsWith<BalModel>(problem, lambda, bounds, loss, num_threads, sys);
  } else {
    WithPhotoModel(sys->layout.max_intrinsics_block(), [&]<class Model>() {
      FormRcsWith<Model>(problem, lambda, bounds, loss, num_threads, sys);
    });
  }
}

void DampCameraBlocks(double lambda, const DampingBounds& bounds,
                      const std::vector<double>& camera_side_jtj_diagonal,
                      BsmcMatrix* S, int32_t num_block_rows) {
  const int32_t n = num_block_rows < 0 ? S->num_block_rows() : num_block_rows;
  for (int32_t i = 0; i < n; ++i) {
    const int c = S->block_size(i);
    double* block = S->block_values(S->diagonal_block(i));
    const double* diag = camera_side_jtj_diagonal.data() + S->scalar_offset(i);
    for (int d = 0; d < c; ++d) block[d * c + d] += lambda * bounds.Clamp(diag[d]);
  }
}

}  // namespace dba
