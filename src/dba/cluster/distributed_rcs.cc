// The RCS spread over the ranks; see distributed_rcs.h.
#include "dba/cluster/distributed_rcs.h"

#include "dba/cluster/rcs_row_plan.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "dba/cluster/block_transfer.h"
#include "dba/common/memory.h"
#include "dba/solver/block_jacobi.h"
#include "dba/solver/pcg.h"
#include "dba/solver/pcg_rcs_solver.h"
#include "dba/solver/two_level_preconditioner.h"

namespace dba {
namespace {

// One exchange's buffers: per rank, what goes out and what comes in, and
// the spans Communicator::Exchange takes.
struct Messages {
  explicit Messages(int ranks) : out(ranks), in(ranks), send(ranks), recv(ranks) {}
  // Buffers of these sizes for rank q (0: nothing to or from it).
  void Size(int q, int64_t out_size, int64_t in_size) {
    out[q].resize(out_size);
    in[q].resize(in_size);
    send[q] = std::span<const double>(out[q]);
    recv[q] = std::span<double>(in[q]);
  }
  std::vector<std::vector<double>> out, in;
  std::vector<std::span<const double>> send;
  std::vector<std::span<double>> recv;
};

// Values of a sub-RCS summed before their pages go back (16 MiB).
constexpr int64_t kReturnChunk = int64_t{1} << 21;

// Every rank sends lists[q] to rank q and gets rank q's list for it (sizes
// exchanged first). The own entry is passed through.
template <typename T>
std::vector<std::vector<T>> ExchangeLists(Communicator* comm, Traffic t,
                                          const std::vector<std::vector<T>>& lists) {
  const int n = comm->size();
  std::vector<int64_t> send_count(n), recv_count(n);
  for (int q = 0; q < n; ++q) send_count[q] = static_cast<int64_t>(lists[q].size());
  std::vector<std::span<const int64_t>> sc(n);
  std::vector<std::span<int64_t>> rc(n);
  for (int q = 0; q < n; ++q) {
    sc[q] = std::span<const int64_t>(&send_count[q], 1);
    rc[q] = std::span<int64_t>(&recv_count[q], 1);
  }
  comm->Exchange(t, sc, rc);
  std::vector<std::vector<T>> received(n);
  std::vector<std::span<const T>> s(n);
  std::vector<std::span<T>> r(n);
  for (int q = 0; q < n; ++q) {
    if (q == comm->rank()) {
      received[q] = lists[q];
      continue;
    }
    received[q].resize(recv_count[q]);
    s[q] = std::span<const T>(lists[q]);
    r[q] = std::span<T>(received[q]);
  }
  comm->Exchange(t, s, r);
  return received;
}

// Scalars of the listed block rows of `m`'s layout, back to back.
int64_t ScalarsOf(const BsmcMatrix& m, const std::vector<int32_t>& rows) {
  int64_t n = 0;
  for (int32_t i : rows) n += m.block_size(i);
  return n;
}

// out[...] = v at the rows' scalar offsets (gather), or v at the offsets +=
// in (scatter-add).
double* GatherRows(const BsmcMatrix& m, const std::vector<int32_t>& rows, const double* v,
                   double* out) {
  for (int32_t i : rows) out = std::copy_n(v + m.scalar_offset(i), m.block_size(i), out);
  return out;
}
const double* AddRows(const BsmcMatrix& m, const std::vector<int32_t>& rows, const double* in,
                      double* v) {
  for (int32_t i : rows) {
    double* o = v + m.scalar_offset(i);
    for (int d = 0; d < m.block_size(i); ++d) o[d] += *in++;
  }
  return in;
}
const double* SetRows(const BsmcMatrix& m, const std::vector<int32_t>& rows, const double* in,
                      double* v) {
  for (int32_t i : rows) {
    std::copy_n(in, m.block_size(i), v + m.scalar_offset(i));
    in += m.block_size(i);
  }
  return in;
}

// A row's coarse basis as 32 doubles (flags, A, B, C, D) and back.
constexpr int kPackedBasis = 32;
void PackBasis(const CoarseRowBasis& N, double* out) {
  out[0] = N.rigid ? 1.0 : 0.0;
  out[1] = N.scale ? 1.0 : 0.0;
  std::copy_n(N.A.data(), 9, out + 2);
  std::copy_n(N.B.data(), 9, out + 11);
  std::copy_n(N.C.data(), 9, out + 20);
  std::copy_n(N.D.data(), 3, out + 29);
}
CoarseRowBasis UnpackBasis(const double* in) {
  CoarseRowBasis N;
  N.rigid = in[0] != 0.0;
  N.scale = in[1] != 0.0;
  std::copy_n(in + 2, 9, N.A.data());
  std::copy_n(in + 11, 9, N.B.data());
  std::copy_n(in + 20, 9, N.C.data());
  std::copy_n(in + 29, 3, N.D.data());
  return N;
}

// The two-level preconditioner's coarse matrix R S Rᵀ summed on the main
// rank from every rank's part (its own rows' blocks, in the global
// aggregate numbering), factorized there; a solve gathers R r from the
// ranks' aggregates and sends each rank its part of the solution.
// Collective: every call on every rank at once (the preconditioner's Update
// and Apply are, inside PCG). The symbolic phase is the first Factorize.
class GatheredCoarseSolver : public CholeskySolver {
 public:
  // This rank's aggregates: [first, end) of the global numbering.
  GatheredCoarseSolver(Communicator* comm, int32_t first, int32_t end)
      : comm_(comm), first_(first), end_(end) {}

  bool Factorize(const BsmcMatrix& part) override {
    const int ranks = comm_->size(), me = comm_->rank();
    if (range_.empty()) Analyse(part);
    std::vector<std::span<const double>> send(ranks);
    std::vector<std::span<double>> recv(ranks);
    std::vector<std::vector<double>> in(ranks);
    std::vector<double> mine;  // the blocks this rank writes, packed
    for (int64_t b : blocks_) {
      mine.insert(mine.end(), part.values().data() + part.value_offset(b),
                  part.values().data() + part.value_offset(b + 1));
    }
    if (me != 0) {
      send[0] = std::span<const double>(mine);
    } else {
      for (int q = 1; q < ranks; ++q) {
        in[q].resize(sizes_[q]);
        recv[q] = std::span<double>(in[q]);
      }
    }
    comm_->Exchange(Traffic::kReduction, send, recv);
    int32_t ok = 0;
    if (me == 0) {
      coarse_.SetZero();
      for (int q = 0; q < ranks; ++q) {
        const double* v = q == 0 ? mine.data() : in[q].data();
        for (int64_t gb : map_[q]) {
          double* o = coarse_.block_values(gb);
          const int64_t n = coarse_.value_offset(gb + 1) - coarse_.value_offset(gb);
          for (int64_t k = 0; k < n; ++k) o[k] += v[k];
          v += n;
        }
      }
      ok = solver_->Factorize(coarse_) ? 1 : 0;
    }
    comm_->Broadcast(Traffic::kReduction, &ok);
    return ok != 0;
  }

  // b, x: the whole coarse vector; this rank's aggregates are read from b
  // and written to x (may alias).
  void SolveFactored(const double* b, double* x) override {
    const int ranks = comm_->size(), me = comm_->rank();
    std::vector<std::span<const double>> send(ranks);
    std::vector<std::span<double>> recv(ranks);
    if (me != 0) {
      send[0] = std::span<const double>(b + range_[2 * me], b + range_[2 * me + 1]);
      recv[0] = std::span<double>(x + range_[2 * me], x + range_[2 * me + 1]);
      comm_->Exchange(Traffic::kReduction, send, {});
      comm_->Exchange(Traffic::kReduction, {}, recv);
      return;
    }
    std::fill(rc_.begin(), rc_.end(), 0.0);
    for (int q = 0; q < ranks; ++q) {
      recv[q] = std::span<double>(rc_.data() + range_[2 * q], rc_.data() + range_[2 * q + 1]);
    }
    std::copy(b + range_[0], b + range_[1], rc_.data() + range_[0]);
    recv[0] = {};
    comm_->Exchange(Traffic::kReduction, {}, recv);
    solver_->SolveFactored(rc_.data(), rc_.data());
    for (int q = 1; q < ranks; ++q) {
      send[q] = std::span<const double>(rc_.data() + range_[2 * q], rc_.data() + range_[2 * q + 1]);
    }
    comm_->Exchange(Traffic::kReduction, send, {});
    std::copy(rc_.data() + range_[0], rc_.data() + range_[1], x + range_[0]);
  }

  // The main rank's factorization is dense or sparse by the coarse size.
  LinearSolverType type() const override { return LinearSolverType::kAuto; }
  int64_t MemoryBytes() const override {
    return solver_ ? solver_->MemoryBytes() + coarse_.ValueBytes() + coarse_.StructureBytes() : 0;
  }

 private:
  // Every rank's coarse pattern and scalar range to the main rank, which
  // builds the coarse matrix over their union and the maps.
  void Analyse(const BsmcMatrix& part) {
    const int ranks = comm_->size(), me = comm_->rank();
    const int64_t mine[2] = {part.scalar_offset(first_), part.scalar_offset(end_)};
    std::vector<int64_t> ranges(2 * ranks, 0);
    std::copy_n(mine, 2, ranges.data() + 2 * me);
    comm_->AllreduceSum(Traffic::kDistribution, ranges);
    range_ = ranges;
    std::vector<std::vector<uint64_t>> lists(ranks);
    // The blocks this rank's rows write: its aggregates' diagonal blocks and
    // the off-diagonal ones (the other diagonal blocks are BSMC's, zero).
    std::vector<uint64_t> pattern;
    for (int32_t i = 0; i < part.num_block_rows(); ++i) {
      for (int64_t b = part.row_begin(i); b < part.row_end(i); ++b) {
        if (part.block_col(b) == i && (i < first_ || i >= end_)) continue;
        blocks_.push_back(b);
        pattern.push_back(PackBlock(i, part.block_col(b)));
      }
    }
    // Every aggregate's diagonal block on the main rank, written or not.
    if (me == 0) {
      for (int32_t i = 0; i < part.num_block_rows(); ++i) pattern.push_back(PackBlock(i, i));
    }
    lists[0] = pattern;
    const auto patterns = ExchangeLists(comm_, Traffic::kDistribution, lists);
    if (me != 0) return;
    std::vector<uint64_t> all;
    for (int q = 0; q < ranks; ++q) all.insert(all.end(), patterns[q].begin(), patterns[q].end());
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    std::vector<int32_t> sizes(part.num_block_rows());
    for (int32_t i = 0; i < part.num_block_rows(); ++i) sizes[i] = part.block_size(i);
    coarse_ = BsmcMatrix::BuildFromPattern(std::move(sizes), all);
    map_.assign(ranks, {});
    sizes_.assign(ranks, 0);
    for (int q = 0; q < ranks; ++q) {
      // The main rank's own list ends with every diagonal block, not sent.
      const size_t sent = q == 0 ? blocks_.size() : patterns[q].size();
      for (size_t k = 0; k < sent; ++k) {
        const uint64_t blk = patterns[q][k];
        const int64_t gb = coarse_.FindBlock(PackedRow(blk), PackedCol(blk));
        if (gb < 0) throw std::logic_error("DistributedRcs: a rank's block is not in the coarse pattern");
        map_[q].push_back(gb);
        sizes_[q] += coarse_.value_offset(gb + 1) - coarse_.value_offset(gb);
      }
    }
    solver_ = MakeCholeskySolver(coarse_, 1024);
    rc_.assign(coarse_.num_rows(), 0.0);
  }

  Communicator* comm_;
  int32_t first_, end_;
  std::vector<int64_t> range_;  // per rank: scalar begin, end of its aggregates
  std::vector<int64_t> blocks_;  // this rank's blocks that it writes
  // Main rank only:
  BsmcMatrix coarse_;
  std::vector<std::vector<int64_t>> map_;  // per rank: its blocks' coarse blocks
  std::vector<int64_t> sizes_;             // per rank: doubles of its part
  std::unique_ptr<CholeskySolver> solver_;
  std::vector<double> rc_;
};

// The owners: each row's by the all-reduced keys (the rank with the most
// values in the row of the symmetric matrix, whatever the rows' numbering),
// then balanced over the ranks that form by `weight`, the values each row
// stores (rcs_row_plan.h).
std::vector<int32_t> ChooseOwners(Communicator* comm, bool has_points,
                                  const std::vector<int64_t>& counts, std::vector<int64_t> weight,
                                  const std::vector<int32_t>& order) {
  const int ranks = comm->size();
  std::vector<int64_t> key = OwnerKeys(counts, ranks, comm->rank());
  comm->AllreduceMax(Traffic::kDistribution, key);
  std::vector<int32_t> owner = OwnersFromKeys(key, ranks);
  for (int64_t& w : weight) w += 1;  // a row nobody sees still counts
  comm->AllreduceSum(Traffic::kDistribution, weight);
  std::vector<int64_t> forms(ranks, 0);
  forms[comm->rank()] = has_points ? 1 : 0;
  comm->AllreduceSum(Traffic::kDistribution, forms);
  BalanceOwnerLoad(weight, forms, &owner, order);
  return owner;
}

}  // namespace

// Who sends what to whom, fixed in the symbolic phase.
struct DistributedRcs::Plan {
  // Reduce-scatter: per destination, the sub-RCS blocks and rows sent there
  // (in this order in the message); per source, the own blocks and rows its
  // message adds into.
  std::vector<std::vector<int64_t>> send_blocks, recv_blocks;
  std::vector<std::vector<uint8_t>> send_transposed;  // SubRcsSendPlan::transposed
  std::vector<std::vector<int32_t>> send_rows, recv_rows;
  std::vector<int64_t> send_size, recv_size;  // doubles
  // Halo: per rank, the own rows whose x it needs, and the halo rows it owns.
  std::vector<std::vector<int32_t>> halo_send, halo_recv;
  // SpreadStep: per rank, the own rows its points see, and the sub rows it
  // owns.
  std::vector<std::vector<int32_t>> step_send, step_recv;
  // Main rank: each rank's own rows (global ids), for the whole δc.
  std::vector<std::vector<int32_t>> own_rows_of;
  // Product scratch per rank: halo values out and in, their sizes (the
  // scalars of halo_send and halo_recv) and the spans of an exchange.
  std::vector<std::vector<double>> halo_out, halo_in;
  std::vector<int64_t> halo_send_scalars, halo_recv_scalars;
  std::vector<std::span<const double>> halo_send_span;
  std::vector<std::span<double>> halo_recv_span;
};

class DistributedRcs::Operator : public PcgOperator {
 public:
  explicit Operator(const DistributedRcs* rcs) : rcs_(rcs) {}
  int64_t num_rows() const override { return rcs_->S_.scalar_offset(rcs_->n_own_); }
  void Multiply(const double* x, double* y) const override { rcs_->Multiply(x, y); }
  void SumOverRanks(std::span<double> partial) const override {
    rcs_->comm_->AllreduceSum(Traffic::kReduction, partial);
  }
  bool SumsOverRanks() const override { return rcs_->comm_->size() > 1; }

 private:
  const DistributedRcs* rcs_;
};

DistributedRcs::~DistributedRcs() = default;

DistributedRcs::DistributedRcs(Communicator* comm, std::vector<int32_t> global_block_sizes,
                               const BsmcMatrix* sub, std::vector<int32_t> sub_rows,
                               const LinearSolverOptions& options,
                               const std::vector<CoarseRowBasis>& global_bases)
    : comm_(comm),
      global_sizes_(std::move(global_block_sizes)),
      sub_(sub),
      sub_rows_(std::move(sub_rows)),
      plan_(std::make_unique<Plan>()),
      options_(options) {
  const int ranks = comm->size(), me = comm->rank();
  const int32_t n_global = static_cast<int32_t>(global_sizes_.size());
  global_offset_.assign(n_global + 1, 0);
  for (int32_t g = 0; g < n_global; ++g) global_offset_[g + 1] = global_offset_[g] + global_sizes_[g];
  order_ = options_.aggregation_order;
  int64_t ordered = static_cast<int64_t>(order_.size());
  comm->Broadcast(Traffic::kDistribution, &ordered);
  order_.resize(ordered);
  comm->Broadcast(Traffic::kDistribution, std::span<int32_t>(order_));
  owner_ = ChooseOwners(comm, sub_ != nullptr, SymmetricRowValueCounts(sub_, sub_rows_, n_global),
                        RowValueCounts(sub_, sub_rows_, n_global), order_);
  Plan& plan = *plan_;
  plan.own_rows_of.assign(ranks, {});
  for (int32_t g = 0; g < n_global; ++g) plan.own_rows_of[owner_[g]].push_back(g);
  const std::vector<int32_t> own = plan.own_rows_of[me];
  n_own_ = static_cast<int32_t>(own.size());
  if (me != 0) {  // only the main rank needs every rank's rows
    for (int q = 0; q < ranks; ++q) {
      if (q != me) std::vector<int32_t>().swap(plan.own_rows_of[q]);
    }
  }

  // The sub-RCS's blocks and rows to their owners; what the others send here.
  SubRcsSendPlan send = PlanSubRcsSends(sub_, sub_rows_, owner_, ranks);
  const auto patterns = ExchangeLists(comm, Traffic::kDistribution, send.pattern);
  const auto row_ids = ExchangeLists(comm, Traffic::kDistribution, send.row_ids);
  plan.send_size = SendSizes(sub_, send);
  plan.send_blocks = std::move(send.blocks);
  plan.send_transposed = std::move(send.transposed);
  plan.send_rows = std::move(send.rows);
  std::vector<std::vector<uint64_t>>().swap(send.pattern);

  // Local numbering: own rows, then the halo; S over them.
  local_rows_ = LocalRows(own, patterns, owner_, me);
  std::vector<int32_t> local_of(n_global, -1);
  std::vector<int32_t> sizes(local_rows_.size());
  for (size_t l = 0; l < local_rows_.size(); ++l) {
    local_of[local_rows_[l]] = static_cast<int32_t>(l);
    sizes[l] = global_sizes_[local_rows_[l]];
  }
  S_ = BsmcMatrix::BuildFromPattern(
      std::move(sizes), LocalPattern(static_cast<int32_t>(local_rows_.size()), patterns, local_of));
  S_.ZeroValuesAndReturnPages();  // zero until the sums land
  ReceivePlan receive = PlanReceives(S_, patterns, row_ids, local_of, global_sizes_);
  plan.recv_blocks = std::move(receive.blocks);
  plan.recv_rows = std::move(receive.rows);
  plan.recv_size = std::move(receive.size);
  const int64_t own_scalars = S_.scalar_offset(n_own_);
  b_.assign(own_scalars, 0.0);
  gradient_.assign(own_scalars, 0.0);
  jtj_diagonal_.assign(own_scalars, 0.0);
  PlanHaloAndStep(local_of);
  MakeSolverStorage(global_bases);
}

// Halo: the halo rows by owner; each owner learns which of its rows to
// send. SpreadStep: the sub rows by owner, likewise.
void DistributedRcs::PlanHaloAndStep(const std::vector<int32_t>& local_of) {
  const int ranks = comm_->size(), me = comm_->rank();
  Communicator* comm = comm_;
  Plan& plan = *plan_;
  std::vector<std::vector<int32_t>> wanted(ranks);
  plan.halo_recv.assign(ranks, {});
  for (size_t l = n_own_; l < local_rows_.size(); ++l) {
    const int q = owner_[local_rows_[l]];
    plan.halo_recv[q].push_back(static_cast<int32_t>(l));
    wanted[q].push_back(local_rows_[l]);
  }
  const auto asked = ExchangeLists(comm, Traffic::kDistribution, wanted);
  plan.halo_send.assign(ranks, {});
  for (int q = 0; q < ranks; ++q) {
    for (int32_t g : asked[q]) plan.halo_send[q].push_back(local_of[g]);
  }
  plan.halo_out.assign(ranks, {});
  plan.halo_in.assign(ranks, {});
  plan.halo_send_scalars.assign(ranks, 0);
  plan.halo_recv_scalars.assign(ranks, 0);
  plan.halo_send_span.assign(ranks, {});
  plan.halo_recv_span.assign(ranks, {});
  for (int q = 0; q < ranks; ++q) {
    if (q == me) continue;
    plan.halo_send_scalars[q] = ScalarsOf(S_, plan.halo_send[q]);
    plan.halo_recv_scalars[q] = ScalarsOf(S_, plan.halo_recv[q]);
    plan.halo_out[q].resize(std::max(plan.halo_send_scalars[q], plan.halo_recv_scalars[q]));
    plan.halo_in[q].resize(plan.halo_out[q].size());
  }

  // SpreadStep: the sub rows by owner; each owner learns which rows to send.
  std::vector<std::vector<int32_t>> step_ids(ranks);
  plan.step_recv.assign(ranks, {});
  for (int32_t i = 0; sub_ != nullptr && i < sub_->num_block_rows(); ++i) {
    const int q = owner_[sub_rows_[i]];
    plan.step_recv[q].push_back(i);
    step_ids[q].push_back(sub_rows_[i]);
  }
  const auto step_asked = ExchangeLists(comm, Traffic::kDistribution, step_ids);
  plan.step_send.assign(ranks, {});
  for (int q = 0; q < ranks; ++q) {
    for (int32_t g : step_asked[q]) plan.step_send[q].push_back(local_of[g]);
  }
}

// The solver's storage: the product, the preconditioner, PCG's vectors.
void DistributedRcs::MakeSolverStorage(const std::vector<CoarseRowBasis>& global_bases) {
  const int64_t own_scalars = S_.scalar_offset(n_own_);
  multiplier_ = std::make_unique<SymmetricMultiplier>(S_, options_.num_threads,
                                                      options_.pcg.product_precision());
  if (options_.preconditioner == PreconditionerType::kTwoLevel) {
    BuildTwoLevel(global_bases);
  } else {
    preconditioner_ =
        std::make_unique<BlockJacobiPreconditioner>(S_, options_.num_threads, n_own_);
  }
  operator_ = std::make_unique<Operator>(this);
  options_.pcg.num_threads = options_.num_threads;
  scratch_.Resize(own_scalars, kOneReductionPcgVectors);
  delta_.assign(own_scalars, 0.0);
  x_ext_.assign(S_.num_rows(), 0.0);
  y_ext_.assign(S_.num_rows(), 0.0);
}

// This rank's own rows (local indices) in the aggregation's order (the
// cameras' places): the aggregates are then the same sets whatever the
// cameras' numbering, as in one process; empty (row order) without one.
std::vector<int32_t> DistributedRcs::OwnAggregationOrder() const {
  if (order_.empty()) return {};
  std::vector<int32_t> place(order_.size());
  for (size_t k = 0; k < order_.size(); ++k) place[order_[k]] = static_cast<int32_t>(k);
  std::vector<int32_t> order(n_own_);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int32_t a, int32_t b) { return place[local_rows_[a]] < place[local_rows_[b]]; });
  return order;
}

// The two-level preconditioner on this rank's rows: the bases of its rows
// (own and halo) from the main rank, aggregates of its own rows numbered
// after the lower ranks', scale columns settled per aggregate, the halo
// rows' aggregates and settled bases from their owners.
void DistributedRcs::BuildTwoLevel(const std::vector<CoarseRowBasis>& global_bases) {
  const int ranks = comm_->size(), me = comm_->rank();
  const Plan& plan = *plan_;
  const int32_t n_local = S_.num_block_rows();
  int32_t with_bases = global_bases.empty() ? 0 : 1;
  comm_->Broadcast(Traffic::kDistribution, &with_bases);
  std::vector<CoarseRowBasis> bases;
  if (with_bases != 0) {
    std::vector<std::vector<int32_t>> lists(ranks);
    lists[0] = local_rows_;
    const auto asked = ExchangeLists(comm_, Traffic::kDistribution, lists);
    std::vector<std::vector<double>> packed(ranks);
    if (me == 0) {
      for (int q = 0; q < ranks; ++q) {
        packed[q].resize(asked[q].size() * kPackedBasis);
        for (size_t k = 0; k < asked[q].size(); ++k) {
          PackBasis(global_bases[asked[q][k]], packed[q].data() + k * kPackedBasis);
        }
      }
    }
    const auto got = ExchangeLists(comm_, Traffic::kDistribution, packed);
    bases.resize(n_local);
    for (int32_t l = 0; l < n_local; ++l) bases[l] = UnpackBasis(got[0].data() + l * kPackedBasis);
  }
  const std::vector<uint8_t> kind = BasisKinds(S_, bases);
  std::vector<int32_t> aggregate =
      AggregateBlockRows(S_, options_.coarse_aggregate_size, kind, n_own_, OwnAggregationOrder());
  const int32_t own_aggregates =
      aggregate.empty() ? 0 : *std::max_element(aggregate.begin(), aggregate.end()) + 1;
  if (with_bases != 0) {  // on every rank, even one without rows: collective
    std::vector<CoarseRowBasis> own(bases.begin(), bases.begin() + n_own_);
    // The "fewer than two scaled aggregates" rule counts all ranks'.
    const int64_t mine = ScaledAggregates(aggregate, own_aggregates, own);
    std::vector<int64_t> scaled(1, mine);
    comm_->AllreduceSum(Traffic::kDistribution, scaled);
    SettleScaleColumns(aggregate, own_aggregates, &own, scaled[0] - mine);
    std::copy(own.begin(), own.end(), bases.begin());
  }
  std::vector<int64_t> counts(ranks, 0);
  counts[me] = own_aggregates;
  comm_->AllreduceSum(Traffic::kDistribution, counts);
  int64_t first = 0, total = 0;
  for (int q = 0; q < ranks; ++q) {
    if (q < me) first += counts[q];
    total += counts[q];
  }
  for (int32_t& a : aggregate) a += static_cast<int32_t>(first);
  std::vector<int64_t> sizes(total, 0);
  for (int32_t l = 0; l < n_own_; ++l) {
    sizes[aggregate[l]] = S_.block_size(l) + (!bases.empty() && bases[l].scale ? 1 : 0);
  }
  comm_->AllreduceSum(Traffic::kDistribution, sizes);
  // The halo rows' aggregates and bases from their owners.
  std::vector<std::vector<double>> out(ranks);
  const int stride = 1 + (bases.empty() ? 0 : kPackedBasis);
  for (int q = 0; q < ranks; ++q) {
    if (q == me) continue;
    for (int32_t l : plan.halo_send[q]) {
      out[q].push_back(aggregate[l]);
      if (!bases.empty()) {
        out[q].resize(out[q].size() + kPackedBasis);
        PackBasis(bases[l], out[q].data() + out[q].size() - kPackedBasis);
      }
    }
  }
  const auto in = ExchangeLists(comm_, Traffic::kDistribution, out);
  aggregate.resize(n_local, 0);
  for (int q = 0; q < ranks; ++q) {
    if (q == me) continue;
    for (size_t k = 0; k < plan.halo_recv[q].size(); ++k) {
      const int32_t l = plan.halo_recv[q][k];
      const double* v = in[q].data() + k * stride;
      aggregate[l] = static_cast<int32_t>(v[0]);
      if (!bases.empty()) bases[l] = UnpackBasis(v + 1);
    }
  }
  preconditioner_ = std::make_unique<TwoLevelPreconditioner>(
      S_, options_.num_threads, n_own_, std::move(aggregate),
      std::vector<int32_t>(sizes.begin(), sizes.end()), std::move(bases),
      std::make_unique<GatheredCoarseSolver>(comm_, static_cast<int32_t>(first),
                                             static_cast<int32_t>(first + own_aggregates)));
}

RcsTotals DistributedRcs::Reduce(const RcsSystem* sub, bool with_pose_terms,
                                 const std::vector<PoseRowTerm>& pose_terms) {
  const int ranks = comm_->size(), me = comm_->rank();
  const Plan& plan = *plan_;
  // Messages to the other owners: the blocks' values, then b, g and diag(U)
  // of each row.
  Messages m(ranks);
  for (int q = 0; q < ranks; ++q) {
    if (q == me) continue;
    m.Size(q, sub != nullptr ? plan.send_size[q] : 0, plan.recv_size[q]);
    if (sub != nullptr) {
      double* o = m.out[q].data();
      for (size_t k = 0; k < plan.send_blocks[q].size(); ++k) {
        o = CopyBlock(sub->S, plan.send_blocks[q][k], plan.send_transposed[q][k] != 0, o);
      }
      for (const std::vector<double>* v : {&sub->b, &sub->camera_side_gradient,
                                           &sub->camera_side_jtj_diagonal}) {
        o = GatherRows(sub->S, plan.send_rows[q], v->data(), o);
      }
    }
  }
  comm_->Exchange(Traffic::kSubRcs, m.send, m.recv);
  std::vector<std::vector<double>>().swap(m.out);

  // S's values read zero when their pages were given back after the last
  // Solve (or at construction): they take memory again as the sums land.
  S_.SetZero();
  std::fill(b_.begin(), b_.end(), 0.0);
  std::fill(gradient_.begin(), gradient_.end(), 0.0);
  std::fill(jtj_diagonal_.begin(), jtj_diagonal_.end(), 0.0);
  // Summed in rank order, the own sub-system at its place.
  for (int p = 0; p < ranks; ++p) {
    if (p == me) {
      if (sub == nullptr) continue;
      // The sub-RCS's pages go back to the system as they are summed (its
      // other owners' blocks are in their messages already): it shrinks
      // while the own rows fill.
      const double* sub_values = sub->S.values().data();
      int64_t returned = 0;  // values of the sub-RCS given back
      for (size_t k = 0; k < plan.send_blocks[me].size(); ++k) {
        const int64_t b = plan.send_blocks[me][k];
        AddToBlock(sub->S.block_values(b), plan.send_transposed[me][k] != 0, plan.recv_blocks[me][k],
                   &S_);
        if (sub->S.value_offset(b + 1) - returned >= kReturnChunk) {
          ReturnPages(const_cast<double*>(sub_values) + returned,
                      (sub->S.value_offset(b + 1) - returned) * 8);
          returned = sub->S.value_offset(b + 1);
        }
      }
      const std::vector<double>* from[3] = {&sub->b, &sub->camera_side_gradient,
                                            &sub->camera_side_jtj_diagonal};
      std::vector<double>* to[3] = {&b_, &gradient_, &jtj_diagonal_};
      for (int v = 0; v < 3; ++v) {
        for (size_t k = 0; k < plan.send_rows[me].size(); ++k) {
          const double* in = from[v]->data() + sub->S.scalar_offset(plan.send_rows[me][k]);
          const int32_t l = plan.recv_rows[me][k];
          double* out = to[v]->data() + S_.scalar_offset(l);
          for (int d = 0; d < S_.block_size(l); ++d) out[d] += in[d];
        }
      }
      continue;
    }
    const double* v = m.in[p].data();
    for (int64_t lb : plan.recv_blocks[p]) v = AddToBlock(v, false, lb, &S_);
    for (std::vector<double>* vec : {&b_, &gradient_, &jtj_diagonal_}) {
      v = AddRows(S_, plan.recv_rows[p], v, vec->data());
    }
    std::vector<double>().swap(m.in[p]);
  }

  if (with_pose_terms) AddPoseTerms(pose_terms);

  double sums[4] = {0.0, 0.0, 0.0, 0.0};
  double max_gradient = 0.0;
  if (sub != nullptr) {
    sums[0] = sub->cost;
    sums[1] = sub->residuals.squared;
    sums[2] = sub->residuals.inlier_squared;
    sums[3] = sub->residuals.inliers;
    max_gradient = sub->max_abs_point_gradient;
  }
  for (double g : gradient_) max_gradient = std::max(max_gradient, std::abs(g));
  comm_->AllreduceSum(Traffic::kControl, sums);
  comm_->AllreduceMax(Traffic::kControl, std::span<double>(&max_gradient, 1));
  RcsTotals totals;
  totals.cost = sums[0];
  totals.residuals = {sums[1], sums[2], sums[3]};
  totals.max_abs_gradient = max_gradient;
  return totals;
}

// The main rank sends each owner its rows' terms (row, JᵀJ, Jᵀr: 43 doubles
// each); every owner adds its own in the main rank's order.
void DistributedRcs::AddPoseTerms(const std::vector<PoseRowTerm>& pose_terms) {
  constexpr int kPacked = 1 + 36 + 6;
  std::vector<double> mine;
  if (comm_->is_main()) {
    std::vector<std::vector<double>> out(comm_->size());
    for (const PoseRowTerm& t : pose_terms) {
      std::vector<double>& o = out[owner_[t.row]];
      o.push_back(t.row);
      o.insert(o.end(), t.JtJ.data(), t.JtJ.data() + 36);
      o.insert(o.end(), t.g.data(), t.g.data() + 6);
    }
    for (int q = 1; q < comm_->size(); ++q) comm_->SendVector(q, Traffic::kSubRcs, out[q]);
    mine = std::move(out[0]);
  } else {
    mine = comm_->RecvVector<double>(0, Traffic::kSubRcs);
  }
  const auto own_begin = local_rows_.begin(), own_end = local_rows_.begin() + n_own_;
  for (size_t k = 0; k + kPacked <= mine.size(); k += kPacked) {
    PoseRowTerm t;
    t.row = static_cast<int32_t>(mine[k]);
    std::copy(&mine[k + 1], &mine[k + 37], t.JtJ.data());
    std::copy(&mine[k + 37], &mine[k + kPacked], t.g.data());
    const auto it = std::lower_bound(own_begin, own_end, t.row);
    if (it == own_end || *it != t.row) throw std::logic_error("a pose term for a row this rank does not own");
    const int32_t l = static_cast<int32_t>(it - own_begin);
    const int64_t o = S_.scalar_offset(l);
    AddPoseRowTerm(t, S_.block_size(l), S_.block_values(S_.diagonal_block(l)), &b_[o],
                   &gradient_[o], &jtj_diagonal_[o]);
  }
}

// One halo exchange: to each rank the values of `from` at `out_rows[q]`;
// from each rank `in_scalars[q]` values into plan.halo_in[q].
void DistributedRcs::ExchangeHalo(const std::vector<std::vector<int32_t>>& out_rows,
                                  const std::vector<int64_t>& in_scalars, const double* from) const {
  Plan& plan = *plan_;
  for (int q = 0; q < comm_->size(); ++q) {
    if (q == comm_->rank()) continue;
    double* end = GatherRows(S_, out_rows[q], from, plan.halo_out[q].data());
    plan.halo_send_span[q] = std::span<const double>(plan.halo_out[q].data(), end);
    plan.halo_recv_span[q] = std::span<double>(plan.halo_in[q].data(), in_scalars[q]);
  }
  comm_->Exchange(Traffic::kHalo, plan.halo_send_span, plan.halo_recv_span);
}

void DistributedRcs::Multiply(const double* x, double* y) const {
  const int me = comm_->rank();
  const Plan& plan = *plan_;
  const int64_t own_scalars = S_.scalar_offset(n_own_);
  std::copy_n(x, own_scalars, x_ext_.data());
  // The halo's x from its owners.
  ExchangeHalo(plan.halo_send, plan.halo_recv_scalars, x_ext_.data());
  for (int q = 0; q < comm_->size(); ++q) {
    if (q != me) SetRows(S_, plan.halo_recv[q], plan.halo_in[q].data(), x_ext_.data());
  }
  multiplier_->Multiply(x_ext_.data(), y_ext_.data());
  // The halo rows' partial sums back to their owners.
  ExchangeHalo(plan.halo_recv, plan.halo_send_scalars, y_ext_.data());
  std::copy_n(y_ext_.data(), own_scalars, y);
  for (int q = 0; q < comm_->size(); ++q) {
    if (q != me) AddRows(S_, plan.halo_send[q], plan.halo_in[q].data(), y);
  }
}

LinearSolveSummary DistributedRcs::Solve(double lambda, const DampingBounds& bounds) {
  DampCameraBlocks(lambda, bounds, jtj_diagonal_, &S_, n_own_);
  preconditioner_->Update(S_);
  if (multiplier_->precision() == ProductPrecision::kMixed) multiplier_->Narrow(&S_);
  const PcgSummary pcg =
      SolvePcg(*operator_, *preconditioner_, b_.data(), delta_.data(), options_.pcg, &scratch_);
  // S's values and the solve's own storage are not read again before the
  // next Reduce refills them.
  S_.ZeroValuesAndReturnPages();
  ReturnSolvePages(preconditioner_.get(), multiplier_.get(), &scratch_);
  return ToLinearSolveSummary(pcg);
}

void DistributedRcs::SpreadStep(std::vector<double>* sub_delta, std::vector<double>* global_delta) {
  const int ranks = comm_->size(), me = comm_->rank();
  const Plan& plan = *plan_;
  Messages m(ranks);
  for (int q = 0; q < ranks; ++q) {
    if (q == me) continue;
    m.Size(q, ScalarsOf(S_, plan.step_send[q]),
           sub_ != nullptr ? ScalarsOf(*sub_, plan.step_recv[q]) : 0);
    GatherRows(S_, plan.step_send[q], delta_.data(), m.out[q].data());
  }
  comm_->Exchange(Traffic::kCameraUpdate, m.send, m.recv);
  if (sub_ != nullptr && sub_delta != nullptr) {
    sub_delta->assign(sub_->num_rows(), 0.0);
    for (int q = 0; q < ranks; ++q) {
      if (q == me) {
        for (size_t k = 0; k < plan.step_recv[me].size(); ++k) {
          const int32_t i = plan.step_recv[me][k], l = plan.step_send[me][k];
          std::copy_n(delta_.data() + S_.scalar_offset(l), S_.block_size(l),
                      sub_delta->data() + sub_->scalar_offset(i));
        }
      } else {
        SetRows(*sub_, plan.step_recv[q], m.in[q].data(), sub_delta->data());
      }
    }
  }
  // The whole δc on the main rank.
  Messages whole(ranks);
  if (me != 0) {
    whole.Size(0, static_cast<int64_t>(delta_.size()), 0);
    std::copy(delta_.begin(), delta_.end(), whole.out[0].begin());
  } else {
    for (int q = 1; q < ranks; ++q) {
      int64_t n = 0;
      for (int32_t g : plan.own_rows_of[q]) n += global_sizes_[g];
      whole.Size(q, 0, n);
    }
  }
  comm_->Exchange(Traffic::kCameraUpdate, whole.send, whole.recv);
  if (me == 0 && global_delta != nullptr) {
    global_delta->assign(global_offset_.back(), 0.0);
    for (int q = 0; q < ranks; ++q) {
      const double* v = q == 0 ? delta_.data() : whole.in[q].data();
      for (int32_t g : plan.own_rows_of[q]) {
        std::copy_n(v, global_sizes_[g], global_delta->data() + global_offset_[g]);
        v += global_sizes_[g];
      }
    }
  }
}

int64_t DistributedRcs::MemoryBytes() const {
  int64_t halo = 0;
  for (const auto& v : plan_->halo_out) halo += 2 * static_cast<int64_t>(v.size()) * 8;
  return S_.ValueBytes() + S_.StructureBytes() + 8 * static_cast<int64_t>(b_.size()) * 4 +
         8 * scratch_.vectors.size() + 2 * 8 * static_cast<int64_t>(x_ext_.size()) +
         preconditioner_->MemoryBytes() + multiplier_->MemoryBytes() + halo;
}

}  // namespace dba
