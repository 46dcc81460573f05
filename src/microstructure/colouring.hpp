#pragma once
// Contact colours: the engine gives each colour its own velocity field, so two grains that may
// touch must differ. Graph: grains whose binder coats come within `gap` of each other (nearest
// periodic image for periodic packings). Greedy colouring, largest degree first (Welsh & Powell
// 1967): deterministic, and at most max degree + 1 colours.
#include "microstructure/packing.hpp"

namespace pbx {

// Sets every grain's colour so that no pair in `pairs` shares one; returns the colours used.
int colour_grains(Packing& p, const std::vector<std::pair<int, int>>& pairs);
// Same with the pairs of contact_pairs(p).
int colour_grains(Packing& p);

// Pairs of grains (i < j) whose coats come within p.contact_gap: the edges the colouring respects.
std::vector<std::pair<int, int>> contact_pairs(const Packing& p);

// Pairs of grains (i < j) whose TATB cores (coats left out) come within `distance`.
std::vector<std::pair<int, int>> core_pairs(const Packing& p, double distance);

// Makes the colours also separate grains whose cores come within `distance` (the grid's reach:
// such grains share nodes). Keeps the packing's colours when they already do; otherwise colours
// again over the union of contact_pairs(p) and core_pairs(p, distance). Returns the number of
// same-colour pairs that were within `distance` (0: colours kept).
int separate_colours_within(Packing& p, double distance);

}  // namespace pbx
