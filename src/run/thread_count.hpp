#pragma once
// How many OpenMP threads a run uses when the user does not say.
//
// Small scenes do not gain from a second thread (each step is a dozen barriers over little work),
// and on a machine whose cores are taken by other processes they lose badly: every barrier waits
// until the scheduler hands the descheduled thread a slice again (measured: a 6 s test ran for over
// 30 minutes with 2 threads while a study held one core; docs/performance.md). So without
// --threads or OMP_NUM_THREADS a run takes one thread per kParticlesPerThread particles, at most
// the cores this process may use (the machine's cores shared among the MPI ranks on the node).
#include <cstddef>
#include <string>

namespace pbx {

inline constexpr std::size_t kParticlesPerThread = 50'000;

struct ThreadChoice {
  int threads = 1;
  std::string chosen_by;  // "--threads", "OMP_NUM_THREADS" or "auto"
  std::string note;       // non-empty: say it on stderr (explicit thread counts that will not pay)
};

// requested: --threads (0 = not given); omp_env: OMP_NUM_THREADS set; omp_default: the OpenMP
// runtime's thread count; procs: cores available; local_ranks: MPI ranks on this node (>= 1).
ThreadChoice choose_threads(int requested, std::size_t particles, bool omp_env, int omp_default, int procs,
                            int local_ranks);

// The same with the environment read (OMP_NUM_THREADS, OMPI_COMM_WORLD_LOCAL_SIZE or MPI_LOCALNRANKS, the core count).
ThreadChoice choose_threads(int requested, std::size_t particles);

}  // namespace pbx
