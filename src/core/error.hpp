#pragma once
#include <stdexcept>
#include <string>

namespace pbx {

// Bad input: a deck key, a file, a command-line value. The message names the key.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A run that went unstable (NaN, J <= 0, particle leaving the grid). The message names the
// particle, step and material; the solver keeps what it wrote before throwing.
struct InstabilityError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// An output file that could not be written whole (a full disk, a quota, a size limit, no
// permission). The message names the file and the system's reason; the file is left as it was
// (atomic writes) and nothing claims to be complete.
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A run stopped by SIGINT/SIGTERM after finishing its step and saving a checkpoint.
struct Interrupted : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace pbx
