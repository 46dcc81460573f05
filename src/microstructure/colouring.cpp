#include "microstructure/colouring.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace pbx {

namespace {
// Pairs whose centres (nearest periodic image) lie closer than reach(a, b).
template <class Reach>
std::vector<std::pair<int, int>> pairs_within(const Packing& p, Reach reach_of) {
  std::vector<std::pair<int, int>> out;
  const int n = static_cast<int>(p.grains.size());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const Grain &a = p.grains[i], &b = p.grains[j];
      Eigen::Vector2d d = b.centre - a.centre;
      if (p.periodic)
        for (int k = 0; k < 2; ++k) d[k] -= p.box[k] * std::round(d[k] / p.box[k]);
      const double reach = reach_of(a, b);
      if (d.squaredNorm() < reach * reach) out.emplace_back(i, j);
    }
  return out;
}
}  // namespace

std::vector<std::pair<int, int>> contact_pairs(const Packing& p) {
  return pairs_within(p, [&](const Grain& a, const Grain& b) {
    return 0.5 * (a.diameter + b.diameter) + a.coat + b.coat + p.contact_gap;
  });
}

std::vector<std::pair<int, int>> core_pairs(const Packing& p, double distance) {
  return pairs_within(p, [&](const Grain& a, const Grain& b) { return 0.5 * (a.diameter + b.diameter) + distance; });
}

int separate_colours_within(Packing& p, double distance) {
  const auto near = core_pairs(p, distance);
  int clashes = 0;
  for (auto [i, j] : near) clashes += p.grains[i].colour == p.grains[j].colour;
  if (clashes == 0) return 0;
  auto pairs = contact_pairs(p);
  pairs.insert(pairs.end(), near.begin(), near.end());
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  p.stats.colours = colour_grains(p, pairs);
  return clashes;
}

int colour_grains(Packing& p) { return colour_grains(p, contact_pairs(p)); }

int colour_grains(Packing& p, const std::vector<std::pair<int, int>>& pairs) {
  const int n = static_cast<int>(p.grains.size());
  std::vector<std::vector<int>> adj(n);
  for (auto [i, j] : pairs) {
    adj[i].push_back(j);
    adj[j].push_back(i);
  }
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return adj[a].size() > adj[b].size(); });
  for (auto& g : p.grains) g.colour = -1;
  int colours = 0;
  std::vector<char> taken;
  for (int i : order) {
    taken.assign(adj[i].size() + 1, 0);
    for (int j : adj[i])
      if (int c = p.grains[j].colour; c >= 0 && c < static_cast<int>(taken.size())) taken[c] = 1;
    int c = 0;
    while (taken[c]) ++c;
    p.grains[i].colour = c;
    colours = std::max(colours, c + 1);
  }
  return colours;
}

}  // namespace pbx
