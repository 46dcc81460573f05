#include "analysis/ensemble.hpp"

#include <cmath>

namespace pbx {

EnsembleStat ensemble_stat(const std::vector<double>& values) {
  EnsembleStat s;
  double sum = 0;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    sum += v;
    ++s.n;
  }
  if (s.n == 0) {
    s.mean = s.std = std::nan("");
    return s;
  }
  s.mean = sum / s.n;
  double ss = 0;
  for (double v : values) {
    if (std::isfinite(v)) ss += (v - s.mean) * (v - s.mean);
  }
  s.std = s.n > 1 ? std::sqrt(ss / (s.n - 1)) : 0.0;
  return s;
}

Json EnsembleStat::to_json() const {
  Json j = Json::object();
  j["mean"] = mean;
  j["std"] = std;
  j["n"] = n;
  return j;
}

}  // namespace pbx
