#pragma once
// The nodal sums of a scatter pass completed across the ranks of a decomposed run
// (docs/architecture.md, "One run over many ranks"). A scatter runs its even strips, then its odd
// strips, each phase's strips at the rank's cuts first (StripBins::visit_order); the exchange
// moves the node lines two ranks share so that every node receives its sums in the one-process
// order, while the rest of each phase runs:
//   start_scatter(); for phase 0, 1: before_lead(phase), the lead strips, after_lead(phase), the
//   others; finish_scatter(). The solver holds a null pointer in a run of one
// process. An interface (one virtual call per phase, never per particle), so the time step needs
// no MPI: the implementation lives in src/distributed/. It is also the reductions' gather of every
// rank's parts of a sum (core/parallel.hpp): a rank's strips are a contiguous range of them.
#include <cstdint>
#include <span>
#include <vector>

#include "core/parallel.hpp"

namespace pbx {

class ScatterExchange : public PartGather {
 public:
  virtual ~ScatterExchange() = default;
  virtual void start_scatter() = 0;         // posts the receives
  virtual void before_lead(int phase) = 0;  // the lines a lead strip of this phase adds to
  virtual void after_lead(int phase) = 0;   // sends the lines the lead strips made
  virtual void finish_scatter() = 0;        // the final lines from the other side

  // Around the strays' serial scatter (taken by every rank when any rank has a stray): before, the
  // zone of 2 x width + 4 node lines around each cut is completed with the neighbour's sums and
  // the sums of the lower ranks' strays; after, this rank's strays go on up the ranks and the final
  // zones come back down. The strays then meet every node in the one-process (index) order.
  // [lo, hi]: the node lines this rank's strays reach; a zone that neither side's strays reach is
  // left alone.
  virtual void before_strays(long lo, long hi) = 0;
  virtual void after_strays() = 0;
  // the largest of every rank's `local` (exact in any order): the time step's speeds, whether a
  // particle jumped a cell, whether any rank must stop
  virtual double max(double local) = 0;
  // each entry of `local` made the largest of every rank's: several decisions in one collective
  virtual void max_each(std::span<double> local) = 0;
  // the node lines (x index, inclusive) whose sums this rank completes: its particles reach no other
  virtual long first_line() const = 0;
  virtual long last_line() const = 0;
  // this rank's strips [first_strip, end_strip)
  virtual long first_strip() const = 0;
  virtual long end_strip() const = 0;
  // The field-overlap raster of every rank merged into each (FieldOverlap::merge_owners per pixel).
  virtual void merge_field_owners(std::vector<std::int32_t>& owner) = 0;
};

}  // namespace pbx
