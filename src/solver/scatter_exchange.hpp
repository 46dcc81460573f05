#pragma once
// The nodal sums of a scatter pass completed across the ranks of a decomposed run
// (docs/architecture.md, "One run over many ranks"). A scatter runs its even strips, then its odd
// strips (grid/strip_bins.hpp); the solver calls after_phase(0) between the two and after_phase(1)
// after the odd ones, and the exchange moves the node lines two ranks share so that every node
// receives its sums in the one-process order. The solver holds a null pointer in a run of one
// process. An interface (one virtual call per phase, never per particle), so the time step needs
// no MPI: the implementation lives in src/distributed/.
namespace pbx {

class ScatterExchange {
 public:
  virtual ~ScatterExchange() = default;
  virtual void after_phase(int phase) = 0;
  // the largest of every rank's `local` (exact in any order): the time step's speeds, whether a
  // particle jumped a cell, whether any rank must stop
  virtual double max(double local) = 0;
  // the node lines (x index, inclusive) whose sums this rank completes: its particles reach no other
  virtual long first_line() const = 0;
  virtual long last_line() const = 0;
};

}  // namespace pbx
