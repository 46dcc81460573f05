#include "run/thread_count.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include <fmt/format.h>
#include <omp.h>

#include "core/parse_number.hpp"

namespace pbx {

ThreadChoice choose_threads(int requested, std::size_t particles, bool omp_env, int omp_default, int procs,
                            int local_ranks) {
  const std::size_t cores = static_cast<std::size_t>(std::max(1, std::max(1, procs) / std::max(1, local_ranks)));
  const int automatic = static_cast<int>(std::min(std::max<std::size_t>(1, particles / kParticlesPerThread), cores));
  ThreadChoice c;
  if (requested > 0) {
    c.threads = requested;
    c.chosen_by = "--threads";
  } else if (omp_env) {
    c.threads = std::max(1, omp_default);
    c.chosen_by = "OMP_NUM_THREADS";
  } else {
    c.threads = automatic;
    c.chosen_by = "auto";
    return c;
  }
  if (c.threads > automatic && particles < kParticlesPerThread * static_cast<std::size_t>(c.threads))
    c.note = fmt::format(
        "{} particles on {} threads (set by {}): below {} particles per thread a thread gains little, and "
        "while other processes hold the cores every step waits for the scheduler (runs many times "
        "slower); without --threads and OMP_NUM_THREADS pbxmpm would use {}",
        particles, c.threads, c.chosen_by, kParticlesPerThread, automatic);
  return c;
}

ThreadChoice choose_threads(int requested, std::size_t particles) {
  // ranks on this machine: Open MPI's count, else MPICH's (Hydra), else one
  int local = 1;
  for (const char* name : {"OMPI_COMM_WORLD_LOCAL_SIZE", "MPI_LOCALNRANKS"}) {
    const char* s = std::getenv(name);
    if (!s) continue;
    const auto v = parse_finite(s);
    if (v && *v >= 1 && *v <= 1e6 && std::floor(*v) == *v) {
      local = static_cast<int>(*v);
      break;
    }
  }
  // OMP_NUM_THREADS is read here, not through omp_get_max_threads(), which an earlier run of this
  // process (a study, a test binary) has changed with omp_set_num_threads; its first entry counts
  // ("4,2" nests), and a value OpenMP would not read leaves OpenMP's own count.
  const char* env = std::getenv("OMP_NUM_THREADS");
  const bool omp_env = env != nullptr && *env != '\0';
  int omp_default = omp_get_max_threads();
  if (omp_env) {
    const std::string first = std::string(env).substr(0, std::string(env).find(','));
    const auto v = parse_finite(first);
    // a value OpenMP cannot read ("abc", "0") would leave its own count without a word
    if (!(v && *v >= 1 && *v <= 1024 && std::floor(*v) == *v))
      throw InputError(
          fmt::format("OMP_NUM_THREADS='{}' is not a thread count (a whole number 1 to 1024, optionally "
                      "followed by ',N' for nested levels); unset it or fix it",
                      env));
    omp_default = static_cast<int>(*v);
  }
  return choose_threads(requested, particles, omp_env, omp_default, omp_get_num_procs(), local);
}

}  // namespace pbx
