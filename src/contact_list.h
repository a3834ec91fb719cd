// Candidate contacts in flat arrays (structure of arrays), with the tangential spring history.
// Rebuilt only between steps; a rebuild carries each surviving pair's history over by a merge
// of the two sorted lists (no map, no per-contact allocation).
#pragma once
#include <cstdint>
#include <vector>

#include "src/broadphase.h"

namespace kiln {

struct ContactList {
  std::vector<int> i, j;        // particle i; particle j (i < j) or segment j
  std::vector<double> spring;   // committed tangential elongation (m)
  std::vector<double> trial;    // elongation at the latest derivative evaluation
  std::vector<double> k, c;     // normal law coefficients for this pair (k_t, c_t are fixed ratios)
  std::vector<uint16_t> law;    // material-pair index (friction, rolling, law flags)
  std::vector<uint8_t> active;  // contact events: acting within the current step (2: not yet known)

  int size() const { return static_cast<int>(i.size()); }
  // Takes the sorted candidate pairs; pairs present before keep their committed elongation.
  void replace(const std::vector<CandidatePair>& fresh);
  void commit() { spring.swap(trial); }
};

}  // namespace kiln
