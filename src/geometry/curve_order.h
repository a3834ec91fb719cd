// Particles ranked along a Hilbert curve, so that discs close in space are close in memory.
//
// A pile that flows mixes: after a while the discs that touch have indices far apart, and every
// contact reads and writes two particles' data at random places, one cache miss each (the
// 100,000-disc bench pile numbered at random took 2-3.5 times as long per step as the same pile
// numbered along its lattice: README, Performance). LAMMPS sorts its atoms into spatial bins
// every 1,000 steps (`atom_modify sort`); kiln ranks them along a Hilbert curve at a neighbour
// rebuild when the ranks of the candidate pairs have drifted apart (DemSystem::rebuild). A
// Hilbert curve keeps neighbours close at every scale: of the pairs of a settled pile, a few per
// cent end up more than a cache's worth of ranks apart, against all of them numbered at random.
//
// Hilbert, "Ueber die stetige Abbildung einer Linie auf ein Flaechenstueck", Math. Ann. 38, 1891;
// the index of a cell by the quadrant recursion of Butz, "Alternative algorithm for Hilbert's
// space-filling curve", IEEE Trans. Computers C-20, 1971.
#pragma once
#include <cstdint>
#include <vector>

#include "src/geometry/broadphase.h"

namespace kiln {

// Bits per axis of the grid the curve visits (32,768 cells a side): the index fits 30 bits.
constexpr int hilbert_bits = 15;

// The position along the Hilbert curve of cell (x, y) of a 2^hilbert_bits square grid.
uint32_t hilbert_index(uint32_t x, uint32_t y);

// order[r]: the particle of rank r along the curve through the places (x, y) of n particles,
// their bounding box mapped onto the grid; particles in one cell keep their index order.
// `keys` is scratch (kept by the caller: no allocation once it has its size).
void hilbert_order(const double* x, const double* y, int n, std::vector<int>& order, std::vector<uint64_t>& keys);

// The share of the pairs (of ranks) more than `window` ranks apart: how far a contact loop
// walking them in order reaches beyond what it has just touched.
double share_apart(const std::vector<CandidatePair>& pairs, int window);

}  // namespace kiln
