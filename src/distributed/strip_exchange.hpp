#pragma once
// The parity exchange of a run decomposed over ranks by strips (docs/architecture.md, "One run
// over many ranks", item 2). Across the cut at strip boundary s (strip s - 1 on the rank below,
// strip s on the rank above) the particles of both strips reach the three node lines b - 1, b,
// b + 1 (b = s x width, a particle reaches one line below its cell and two above). One process sums
// the even strip of the two first, then the odd one on top. So once its even strip at the cut is
// scattered (the first of its phase, StripBins::visit_order) the rank holding it sends those lines
// (every deformable field, every sum the scatter makes) to the other rank, which takes them as they
// are (its own even strips never reach them) and scatters its odd strip at the cut on top, first
// of its odd phase, and sends the final lines back. Every node then holds the one-process bits on
// both ranks; the messages travel while the ranks scatter their other strips.
//
// A message carries only the node-fields that hold mass on the sender (about a quarter of a line's
// entries on the paper specimen): with a shape function whose gradient vanishes with its weight
// (uGIMP, bspline2) an entry without mass holds no sum at all (Solver::reset_grid rests on the
// same fact), so the receiver zeroes the entries it holds and the message leaves out, and ends with
// the bits a message of every entry would give. The linear hat's gradient does not vanish with its
// weight: `sparse` false sends every entry.
#include <mpi.h>

#include <vector>

#include "contact/layer_data.hpp"
#include "grid/grid.hpp"
#include "solver/scatter_exchange.hpp"

namespace pbx {

template <int D>
class StripExchange final : public ScatterExchange {
 public:
  // This rank owns strips [first_strip, end_strip) of `strips` strips `width` cells wide; `layer`
  // holds the binder-layer sums (null or off: none); `sparse`: messages of the mass-holding entries
  // only (a shape function other than the linear hat).
  StripExchange(MPI_Comm comm, Grid<D>& grid, LayerSums<D>* layer, long width, long strips, long first_strip,
                long end_strip, bool sparse);
  void start_scatter() override;
  void before_lead(int phase) override;
  void after_lead(int phase) override;
  void finish_scatter() override;
  void before_strays(long lo, long hi) override;
  void after_strays() override;
  double max(double local) override;
  void max_each(std::span<double> local) override;
  long first_line() const override { return first_line_; }
  long last_line() const override { return last_line_; }
  long first_strip() const override { return first_strip_; }
  long end_strip() const override { return end_strip_; }
  std::vector<double> in_rank_order(const std::vector<double>& mine) override;
  void merge_field_owners(std::vector<std::int32_t>& owner) override;
  // the largest message sent so far, doubles (its entries' indices included)
  std::size_t message_doubles() const { return largest_; }

 private:
  struct Cut {
    int peer;         // the rank across the cut
    long line0;       // first of its three node lines (x index)
    int sends_after;  // the phase after which this rank sends (the one after the other phase, it receives)
  };
  // The stray zone at a cut: node lines [lo, hi] (cut line b - width - 1 to b + width + 2, within
  // the grid), where the strays of the ranks on both sides may meet.
  struct Zone {
    int peer;
    long b, lo, hi;
    bool peer_above;
    bool active = false;         // strays of either side reach it in this scatter
    long line0 = 0, line1 = -1;  // the lines they reach, within [lo, hi]
  };
  template <class F>
  void for_each_node_field(long line0, long line1, F&& f) const;  // node lines [line0, line1]
  std::size_t entry_doubles() const;                              // an entry's index and sums
  std::size_t capacity(long line0, long line1) const;             // doubles of the largest message
  void pack(long line0, long line1, std::vector<double>& buf);
  void unpack(long line0, long line1, const double* buf, std::size_t size);  // a message of `size` doubles
  void take(std::size_t cut);  // waits for the cut's posted receive and unpacks it
  void send_lines(int peer, long line0, long line1, int tag);
  void receive_lines(int peer, long line0, long line1, int tag);
  MPI_Comm comm_;
  Grid<D>& g_;
  LayerSums<D>* layer_;
  std::vector<Cut> cuts_;
  std::vector<Zone> zones_;  // the lower cut's first
  long first_line_ = 0, last_line_ = 0;
  long first_strip_ = 0, end_strip_ = 0;
  bool sparse_;
  std::vector<double> send_[2], recv_[2];  // the parity exchange's, per cut
  MPI_Request send_req_[2] = {MPI_REQUEST_NULL, MPI_REQUEST_NULL}, recv_req_[2] = {MPI_REQUEST_NULL, MPI_REQUEST_NULL};
  std::vector<double> out_, in_;  // the stray zones'
  std::vector<long> entries_;     // the node-fields of the message being packed or unpacked
  std::size_t largest_ = 0;
};

}  // namespace pbx
