#pragma once
// The timed loop the engine benchmarks share: a few warm-up steps (first touch, caches), then
// `steps` steps timed by wall clock and by the process's CPU time, printed as particle-updates per
// second (particles x steps / s), the peak resident memory per particle, and the wall seconds per
// stage of the step (solver/stage_clock.hpp).
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <string>

#include "solver/solver.hpp"

namespace pbx::bench {

struct StepTiming {
  double wall = 0, user = 0, cpu = 0, updates_per_s = 0, peak_rss_mb = 0;
};

template <int D>
StepTiming time_steps(Solver<D>& solver, int steps, int warmup = 5) {
  for (int s = 0; s < warmup; ++s) solver.step();
  solver.stage_clock().clear();
  rusage ru0{};
  getrusage(RUSAGE_SELF, &ru0);
  const auto t0 = std::chrono::steady_clock::now();
  for (int s = 0; s < steps; ++s) solver.step();
  StepTiming r;
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  const auto seconds = [](const timeval& tv) {
    return static_cast<double>(tv.tv_sec) + 1e-6 * static_cast<double>(tv.tv_usec);
  };
  r.user = seconds(ru.ru_utime) - seconds(ru0.ru_utime);
  r.cpu = r.user + seconds(ru.ru_stime) - seconds(ru0.ru_stime);
  r.updates_per_s = static_cast<double>(solver.scene().particles.size()) * steps / r.wall;
  r.peak_rss_mb = static_cast<double>(ru.ru_maxrss) / 1024.0;
  return r;
}

// One line per stage: wall seconds, share of the timed steps, nanoseconds per particle-update.
template <int D>
void print_stages(const Solver<D>& solver, int steps) {
  const StageClock& c = solver.stage_clock();
  const double total = c.total(), updates = static_cast<double>(solver.scene().particles.size()) * steps;
  std::string line = "  stages (wall s, share, ns/particle-update):";
  for (std::size_t s = 0; s < kStageNames.size(); ++s) {
    const double w = c.seconds(static_cast<Stage>(s));
    char buf[128];
    std::snprintf(buf, sizeof buf, "  %s %.3f %.0f%% %.1f", kStageNames[s], w, 100 * w / total, 1e9 * w / updates);
    line += buf;
  }
  std::printf("%s\n", line.c_str());
}

}  // namespace pbx::bench
