#pragma once
// Wall seconds per stage of the time step, summed over a run (run.json "stage_wall_s") and printed
// by the benchmarks, so that a slow run says where its time goes without a profiler. A stage times
// itself with a scope at its top (two clock reads, about 50 ns, against a step of 0.1-100 ms).
// The fused USL particle pass runs G2P, the stress update and P2G chunk by chunk inside one
// parallel loop; its wall time is split between the three in proportion to the thread seconds its
// chunks spent in each (split_pass), so the stages still sum to the steps' wall time.
#include <array>
#include <chrono>
#include <cstddef>

namespace pbx {

enum class Stage : int { rigid_p2g, reset, p2g, contact, grid_update, g2p, stress, bodies, count };

inline constexpr std::array<const char*, static_cast<std::size_t>(Stage::count)> kStageNames = {
    "rigid_p2g", "reset", "p2g", "contact", "grid_update", "g2p", "stress", "bodies"};

class StageClock {
 public:
  using Clock = std::chrono::steady_clock;

  class Scope {
   public:
    Scope(StageClock& c, Stage s) : c_(c), s_(s), t0_(Clock::now()) {}
    ~Scope() { c_.add(s_, std::chrono::duration<double>(Clock::now() - t0_).count()); }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    StageClock& c_;
    Stage s_;
    Clock::time_point t0_;
  };

  [[nodiscard]] Scope scope(Stage s) { return Scope(*this, s); }
  void add(Stage s, double seconds) { wall_[static_cast<std::size_t>(s)] += seconds; }
  // A fused pass of `wall` seconds whose chunks spent the thread seconds g2p, stress and p2g.
  void split_pass(double wall, double g2p, double stress, double p2g) {
    const double sum = g2p + stress + p2g;
    if (!(sum > 0.0)) {
      add(Stage::stress, wall);
      return;
    }
    add(Stage::g2p, wall * g2p / sum);
    add(Stage::stress, wall * stress / sum);
    add(Stage::p2g, wall * p2g / sum);
  }
  double seconds(Stage s) const { return wall_[static_cast<std::size_t>(s)]; }
  double total() const {
    double t = 0;
    for (const double w : wall_) t += w;
    return t;
  }
  void clear() { wall_.fill(0.0); }

 private:
  std::array<double, static_cast<std::size_t>(Stage::count)> wall_{};
};

}  // namespace pbx
