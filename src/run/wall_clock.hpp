#pragma once
// Wall time and memory of this process, as the run driver reports them (run.json, progress).
#include <chrono>
#include <cmath>
#include <string>

#include <fmt/format.h>
#include <sys/resource.h>

namespace pbx {

inline double now_s() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

// Peak resident memory of the process, MB.
inline double peak_memory_mb() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) / 1024.0;
}

// "hh:mm:ss", or "--:--:--" when not known.
inline std::string hms(double s) {
  if (!(s >= 0) || s > 1e7) return "--:--:--";
  const long t = std::lround(s);
  return fmt::format("{:02d}:{:02d}:{:02d}", t / 3600, (t / 60) % 60, t % 60);
}

}  // namespace pbx
