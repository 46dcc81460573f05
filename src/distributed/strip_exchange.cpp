#include "distributed/strip_exchange.hpp"

#include <stdexcept>
#include <string>

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
                                long first_strip, long end_strip)
    : comm_(comm), g_(grid), layer_(layer) {
  int rank = 0, size = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &size);
  if (first_strip >= end_strip || width < 3)
    throw std::invalid_argument("StripExchange: a rank needs at least one strip, and strips three cells");
  // the rank of strip s holds the even strip of a cut when s is even: it sends after the even phase
  if (rank > 0) cuts_.push_back({rank - 1, first_strip * width - 1, first_strip % 2 == 0 ? 0 : 1});
  if (rank < size - 1 && end_strip < strips)
    cuts_.push_back({rank + 1, end_strip * width - 1, (end_strip - 1) % 2 == 0 ? 0 : 1});
  first_line_ = first_strip == 0 ? 0 : first_strip * width - 1;
  last_line_ = end_strip >= strips ? grid.n[0] - 1 : end_strip * width + 1;
  for (std::size_t k = 0; k < cuts_.size(); ++k) {
    pack(cuts_[k], send_[k]);  // sizes the buffers
    recv_[k].assign(send_[k].size(), 0.0);
  }
  // Both sides of every cut must agree on its lines, on who sends first and on the message size:
  // a partition that is not the same on every rank would otherwise hang in the first exchange.
  for (std::size_t k = 0; k < cuts_.size(); ++k) {
    const long mine[3] = {cuts_[k].line0, cuts_[k].sends_after, static_cast<long>(send_[k].size())};
    long theirs[3] = {};
    MPI_Sendrecv(mine, 3, MPI_LONG, cuts_[k].peer, 99, theirs, 3, MPI_LONG, cuts_[k].peer, 99, comm, MPI_STATUS_IGNORE);
    if (theirs[0] != mine[0] || theirs[1] != 1 - mine[1] || theirs[2] != mine[2])
      throw std::runtime_error("StripExchange: ranks " + std::to_string(rank) + " and " +
                               std::to_string(cuts_[k].peer) +
                               " disagree on the cut between them (each must hold its own part of one partition)");
  }
}

// Calls f(entry, doubles per entry) for every entry of cut c's three lines, in the order a message
// carries them (the same order on both sides).
template <int D>
template <class F>
void StripExchange<D>::for_each_entry(const Cut& c, F&& f) const {
  const long n0 = g_.n[0], rows = g_.nodes() / n0;
  for_each_sum(g_, layer_, [&](double* a, int w) {
    for (int fld = 0; fld < g_.deformable; ++fld)
      for (long r = 0; r < rows; ++r)
        for (long x = c.line0; x < c.line0 + 3; ++x)
          f(a + static_cast<std::size_t>(w) * static_cast<std::size_t>(g_.at(fld, r * n0 + x)), w);
  });
}

template <int D>
void StripExchange<D>::pack(const Cut& c, std::vector<double>& buf) const {
  buf.clear();
  for_each_entry(c, [&](const double* e, int w) { buf.insert(buf.end(), e, e + w); });
}

template <int D>
void StripExchange<D>::unpack(const Cut& c, const std::vector<double>& buf) {
  std::size_t k = 0;
  for_each_entry(c, [&](double* e, int w) {
    for (int i = 0; i < w; ++i) e[i] = buf[k++];
  });
}

template <int D>
void StripExchange<D>::after_phase(int phase) {
  std::vector<MPI_Request> req;
  for (std::size_t k = 0; k < cuts_.size(); ++k) {
    const Cut& c = cuts_[k];
    MPI_Request r;
    if (c.sends_after == phase) {
      pack(c, send_[k]);
      MPI_Isend(send_[k].data(), static_cast<int>(send_[k].size()), MPI_DOUBLE, c.peer, phase, comm_, &r);
    } else {
      MPI_Irecv(recv_[k].data(), static_cast<int>(recv_[k].size()), MPI_DOUBLE, c.peer, phase, comm_, &r);
    }
    req.push_back(r);
  }
  if (!req.empty()) MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
  for (std::size_t k = 0; k < cuts_.size(); ++k)
    if (cuts_[k].sends_after != phase) unpack(cuts_[k], recv_[k]);
}

template <int D>
double StripExchange<D>::max(double local) {
  double out = local;
  MPI_Allreduce(&local, &out, 1, MPI_DOUBLE, MPI_MAX, comm_);
  return out;
}

template class StripExchange<2>;
template class StripExchange<3>;

}  // namespace pbx
