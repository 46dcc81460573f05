#pragma once
// Statistics over a microstructure ensemble (several seeds of one condition).
#include <vector>

#include "io/json.hpp"

namespace pbx {

struct EnsembleStat {
  double mean = 0;
  double std = 0;  // sample standard deviation (n - 1); 0 for a single value
  int n = 0;
  Json to_json() const;
};

// Non-finite values are skipped; n = 0 gives NaN mean and std.
EnsembleStat ensemble_stat(const std::vector<double>& values);

}  // namespace pbx
