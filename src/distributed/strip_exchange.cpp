#include "distributed/strip_exchange.hpp"

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "contact/field_overlap.hpp"

namespace pbx {

namespace {

// Calls f(first double, doubles per entry) for every nodal sum a scatter makes (the grid's, and the
// binder layer's when it is on), the entry of field f at node i being at index grid.at(f, i).
template <int D, class F>
void for_each_sum(Grid<D>& g, LayerSums<D>* layer, F&& f) {
  f(g.mass.data(), 1);
  f(g.mom.data()->data(), D);
  f(g.moff.data()->data(), D);
  f(g.vgrad.data()->data(), D);
  f(g.force.data()->data(), D);
  if (layer && !layer->mbond.empty()) {
    f(layer->mref.data()->data(), D);
    f(layer->mdef.data()->data(), D * D);
    f(layer->mbond.data(), 1);
    f(layer->mnorm.data()->data(), D);
    f(layer->minvt.data(), 1);
  }
}

}  // namespace

template <int D>
StripExchange<D>::StripExchange(MPI_Comm comm, Grid<D>& grid, LayerSums<D>* layer, long width, long strips,
                                long first_strip, long end_strip, bool sparse)
    : comm_(comm), g_(grid), layer_(layer), first_strip_(first_strip), end_strip_(end_strip), sparse_(sparse) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  if (first_strip >= end_strip || width < 3)
    throw std::invalid_argument("StripExchange: a rank needs at least one strip, and strips three cells");
  // the rank of strip s holds the even strip of a cut when s is even: it sends after the even phase
  if (rank > 0) cuts_.push_back({rank - 1, first_strip * width - 1, first_strip % 2 == 0 ? 0 : 1});
  if (rank < size - 1 && end_strip < strips)
    cuts_.push_back({rank + 1, end_strip * width - 1, (end_strip - 1) % 2 == 0 ? 0 : 1});
  for (const Cut& c : cuts_) {
    const long b = c.line0 + 1;
    zones_.push_back({c.peer, b, std::max(0L, b - width - 1), std::min(grid.n[0] - 1, b + width + 2), c.peer > rank});
  }
  if (zones_.size() == 2 && !(zones_[0].hi < zones_[1].lo))
    throw std::invalid_argument("StripExchange: rank " + std::to_string(rank) +
                                " holds too few strips for its two stray zones to stay apart");
  first_line_ = first_strip == 0 ? 0 : first_strip * width - 1;
  last_line_ = end_strip >= strips ? grid.n[0] - 1 : end_strip * width + 1;
  for (std::size_t k = 0; k < cuts_.size(); ++k) {
    send_[k].reserve(capacity(cuts_[k].line0, cuts_[k].line0 + 2));
    recv_[k].assign(capacity(cuts_[k].line0, cuts_[k].line0 + 2), 0.0);
  }
  // Both sides of every cut must agree on its lines, on who sends first, on the messages' largest
  // size and on their form: a partition that is not the same on every rank would otherwise hang in
  // the first exchange.
  for (std::size_t k = 0; k < cuts_.size(); ++k) {
    const long mine[4] = {cuts_[k].line0, cuts_[k].sends_after, static_cast<long>(recv_[k].size()), sparse ? 1 : 0};
    long theirs[4] = {};
    MPI_Sendrecv(mine, 4, MPI_LONG, cuts_[k].peer, 99, theirs, 4, MPI_LONG, cuts_[k].peer, 99, comm, MPI_STATUS_IGNORE);
    if (theirs[0] != mine[0] || theirs[1] != 1 - mine[1] || theirs[2] != mine[2] || theirs[3] != mine[3])
      throw std::runtime_error("StripExchange: ranks " + std::to_string(rank) + " and " +
                               std::to_string(cuts_[k].peer) +
                               " disagree on the cut between them (each must hold its own part of one partition)");
  }
}

// Calls f(k) for every node-field k = grid.at(field, node) of node lines [line0, line1], in the
// order a message carries them (the same order on both sides).
template <int D>
template <class F>
void StripExchange<D>::for_each_node_field(long line0, long line1, F&& f) const {
  const long n0 = g_.n[0], rows = g_.nodes() / n0;
  for (int fld = 0; fld < g_.deformable; ++fld)
    for (long r = 0; r < rows; ++r)
      for (long x = line0; x <= line1; ++x) f(g_.at(fld, r * n0 + x));
}

// A message: the count n of its entries, their n node-field indices, then each sum's values for
// those entries (for_each_sum's order). Indices travel as doubles (exact below 2^53).
template <int D>
std::size_t StripExchange<D>::entry_doubles() const {
  std::size_t n = 1;  // its index
  for_each_sum(g_, layer_, [&](double*, int w) { n += static_cast<std::size_t>(w); });
  return n;
}

template <int D>
std::size_t StripExchange<D>::capacity(long line0, long line1) const {
  const std::size_t per_entry = entry_doubles();
  const auto entries = static_cast<std::size_t>(g_.deformable) * static_cast<std::size_t>(g_.nodes() / g_.n[0]) *
                       static_cast<std::size_t>(line1 - line0 + 1);
  return 1 + entries * per_entry;
}

template <int D>
void StripExchange<D>::pack(long line0, long line1, std::vector<double>& buf) {
  entries_.clear();
  for_each_node_field(line0, line1, [&](long k) {
    if (!sparse_ || g_.mass[static_cast<std::size_t>(k)] != 0.0) entries_.push_back(k);
  });
  buf.clear();
  buf.push_back(static_cast<double>(entries_.size()));
  for (const long k : entries_) buf.push_back(static_cast<double>(k));
  for_each_sum(g_, layer_, [&](double* a, int w) {
    for (const long k : entries_) {
      const double* e = a + static_cast<std::size_t>(w) * static_cast<std::size_t>(k);
      buf.insert(buf.end(), e, e + w);
    }
  });
  largest_ = std::max(largest_, buf.size());
}

template <int D>
void StripExchange<D>::unpack(long line0, long line1, const double* buf, std::size_t size) {
  const std::size_t per_entry = entry_doubles();
  const std::size_t n = size >= 1 ? static_cast<std::size_t>(buf[0]) : 0;
  if (size < 1 || size != 1 + n * per_entry)
    throw std::logic_error("StripExchange: a message whose size does not match its entry count");
  entries_.resize(n);
  for (std::size_t j = 0; j < n; ++j) entries_[j] = static_cast<long>(buf[1 + j]);
  // The entries this rank holds and the message leaves out hold nothing on the sender: zero them
  // (before the message's masses arrive, which this test reads). Every entry of the lines is in the
  // message's order, so one cursor walks both.
  std::size_t next = 0;
  for_each_node_field(line0, line1, [&](long k) {
    if (next < n && entries_[next] == k) {
      ++next;
      return;
    }
    if (g_.mass[static_cast<std::size_t>(k)] != 0.0)
      for_each_sum(g_, layer_, [&](double* a, int w) {
        std::fill_n(a + static_cast<std::size_t>(w) * static_cast<std::size_t>(k), w, 0.0);
      });
  });
  if (next != n) throw std::logic_error("StripExchange: a message naming entries outside its lines");
  std::size_t at = 1 + n;
  for_each_sum(g_, layer_, [&](double* a, int w) {
    for (const long k : entries_) {
      double* e = a + static_cast<std::size_t>(w) * static_cast<std::size_t>(k);
      for (int i = 0; i < w; ++i) e[i] = buf[at++];
    }
  });
}

template <int D>
void StripExchange<D>::send_lines(int peer, long line0, long line1, int tag) {
  pack(line0, line1, out_);
  MPI_Send(out_.data(), static_cast<int>(out_.size()), MPI_DOUBLE, peer, tag, comm_);
}

template <int D>
void StripExchange<D>::receive_lines(int peer, long line0, long line1, int tag) {
  const std::size_t cap = capacity(line0, line1);
  if (in_.size() < cap) in_.resize(cap);
  MPI_Status status;
  MPI_Recv(in_.data(), static_cast<int>(cap), MPI_DOUBLE, peer, tag, comm_, &status);
  int got = 0;
  MPI_Get_count(&status, MPI_DOUBLE, &got);
  unpack(line0, line1, in_.data(), static_cast<std::size_t>(got));
}

// The strays' order across ranks. After the parity phases each rank holds its own side of a zone
// (up to the shared lines b - 1 ... b + 1, which both hold), so first each side of every zone
// crosses to the other (tag 10). Then the strays go in index order, which is rank order: a rank
// takes the lower zone as the rank below left it after its strays (tag 11: a chain up the ranks),
// scatters its own, passes its upper zone up, and takes it back final from above (tag 12: the chain
// down), passing its lower zone down. The zones of one rank are apart (checked at construction),
// so a rank's strays meet in its zones only its neighbours' strays.
template <int D>
void StripExchange<D>::before_strays(long lo, long hi) {
  // Which lines of each zone take part: those the strays of either side reach (the others keep the
  // parity phases' sums, complete on the side that reads them). None: the zone is left alone.
  for (Zone& z : zones_) {
    const long mine[2] = {lo, hi};
    long theirs[2] = {};
    MPI_Sendrecv(mine, 2, MPI_LONG, z.peer, 9, theirs, 2, MPI_LONG, z.peer, 9, comm_, MPI_STATUS_IGNORE);
    z.line0 = std::max(z.lo, std::min(lo, theirs[0]));
    z.line1 = std::min(z.hi, std::max(hi, theirs[1]));
    z.active = z.line0 <= z.line1;
  }
  for (const Zone& z : zones_) {
    if (!z.active) continue;
    // this side's lines of the zone (up to the shared lines b - 1 ... b + 1, which both hold) and the other's
    const long mine0 = z.peer_above ? z.line0 : std::max(z.line0, z.b + 2);
    const long mine1 = z.peer_above ? std::min(z.line1, z.b - 2) : z.line1;
    const long theirs0 = z.peer_above ? std::max(z.line0, z.b + 2) : z.line0;
    const long theirs1 = z.peer_above ? z.line1 : std::min(z.line1, z.b - 2);
    out_.clear();
    if (mine0 <= mine1) pack(mine0, mine1, out_);
    const std::size_t cap = theirs0 <= theirs1 ? capacity(theirs0, theirs1) : 0;
    if (in_.size() < cap) in_.resize(cap);
    MPI_Status status;
    MPI_Sendrecv(out_.data(), static_cast<int>(out_.size()), MPI_DOUBLE, z.peer, 10, in_.data(), static_cast<int>(cap),
                 MPI_DOUBLE, z.peer, 10, comm_, &status);
    if (theirs0 <= theirs1) {
      int got = 0;
      MPI_Get_count(&status, MPI_DOUBLE, &got);
      unpack(theirs0, theirs1, in_.data(), static_cast<std::size_t>(got));
    }
  }
  for (const Zone& z : zones_)
    if (z.active && !z.peer_above) receive_lines(z.peer, z.line0, z.line1, 11);
}

template <int D>
void StripExchange<D>::after_strays() {
  for (const Zone& z : zones_)
    if (z.active && z.peer_above) {
      send_lines(z.peer, z.line0, z.line1, 11);
      receive_lines(z.peer, z.line0, z.line1, 12);
    }
  for (const Zone& z : zones_)
    if (z.active && !z.peer_above) send_lines(z.peer, z.line0, z.line1, 12);
}

// A cut's two messages: the side whose strip at the cut is even ("first", sends_after 0) sends its
// lines once that strip is scattered (tag 0); the other side takes them before it scatters its odd
// strip at the cut on top, and sends the final lines back (tag 1). Both receives are posted at the
// start, so a message lands while its receiver works, and a rank waits only when the other side's
// lead strip is later than all its own work before the receive.
template <int D>
void StripExchange<D>::start_scatter() {
  for (std::size_t k = 0; k < cuts_.size(); ++k)
    MPI_Irecv(recv_[k].data(), static_cast<int>(recv_[k].size()), MPI_DOUBLE, cuts_[k].peer,
              cuts_[k].sends_after == 0 ? 1 : 0, comm_, &recv_req_[k]);
}

template <int D>
void StripExchange<D>::take(std::size_t k) {
  MPI_Status status;
  MPI_Wait(&recv_req_[k], &status);
  int got = 0;
  MPI_Get_count(&status, MPI_DOUBLE, &got);
  unpack(cuts_[k].line0, cuts_[k].line0 + 2, recv_[k].data(), static_cast<std::size_t>(got));
}

template <int D>
void StripExchange<D>::before_lead(int phase) {
  if (phase == 1)
    for (std::size_t k = 0; k < cuts_.size(); ++k)
      if (cuts_[k].sends_after == 1) take(k);
}

template <int D>
void StripExchange<D>::after_lead(int phase) {
  for (std::size_t k = 0; k < cuts_.size(); ++k) {
    const Cut& c = cuts_[k];
    if (c.sends_after != phase) continue;
    pack(c.line0, c.line0 + 2, send_[k]);
    MPI_Isend(send_[k].data(), static_cast<int>(send_[k].size()), MPI_DOUBLE, c.peer, phase, comm_, &send_req_[k]);
  }
}

template <int D>
void StripExchange<D>::finish_scatter() {
  for (std::size_t k = 0; k < cuts_.size(); ++k)
    if (cuts_[k].sends_after == 0) take(k);
  for (std::size_t k = 0; k < cuts_.size(); ++k) MPI_Wait(&send_req_[k], MPI_STATUS_IGNORE);
}

template <int D>
double StripExchange<D>::max(double local) {
  double out = local;
  MPI_Allreduce(&local, &out, 1, MPI_DOUBLE, MPI_MAX, comm_);
  return out;
}

template <int D>
void StripExchange<D>::max_each(std::span<double> local) {
  MPI_Allreduce(MPI_IN_PLACE, local.data(), static_cast<int>(local.size()), MPI_DOUBLE, MPI_MAX, comm_);
}

template <int D>
std::vector<double> StripExchange<D>::in_rank_order(const std::vector<double>& mine) {
  int size = 1;
  MPI_Comm_size(comm_, &size);
  const int n = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<std::size_t>(size)), offsets(static_cast<std::size_t>(size), 0);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_);
  for (int r = 1; r < size; ++r)
    offsets[static_cast<std::size_t>(r)] =
        offsets[static_cast<std::size_t>(r - 1)] + counts[static_cast<std::size_t>(r - 1)];
  std::vector<double> all(static_cast<std::size_t>(offsets.back() + counts.back()));
  MPI_Allgatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE, comm_);
  return all;
}

namespace {
extern "C" void merge_owners_op(void* in, void* inout, int* len, MPI_Datatype*) {
  const auto* a = static_cast<const std::int32_t*>(in);
  auto* b = static_cast<std::int32_t*>(inout);
  for (int i = 0; i < *len; ++i) b[i] = FieldOverlap::merge_owners(a[i], b[i]);
}
}  // namespace

template <int D>
void StripExchange<D>::merge_field_owners(std::vector<std::int32_t>& owner) {
  MPI_Op op;
  MPI_Op_create(&merge_owners_op, 1, &op);
  MPI_Allreduce(MPI_IN_PLACE, owner.data(), static_cast<int>(owner.size()), MPI_INT32_T, op, comm_);
  MPI_Op_free(&op);
}

template class StripExchange<2>;
template class StripExchange<3>;

}  // namespace pbx
