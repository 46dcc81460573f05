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

}  // namespace pbx
