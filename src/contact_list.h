// Candidate contacts in flat arrays (structure of arrays), with their history: the tangential
// and rolling springs and the contact frame they are measured from (contact/contact_frame.h).
// Rebuilt only between steps; a rebuild carries each surviving pair's history over by a merge
// of the two sorted lists (no map, no per-contact allocation).
#pragma once
#include <cstdint>
#include <vector>

#include "contact/contact_frame.h"
#include "src/broadphase.h"
#include "src/snapshot.h"

namespace kiln {

struct ContactList {
  std::vector<int> i, j;        // particle i; particle j (i < j) or segment j
  std::vector<double> k, c;     // normal law coefficients for this pair (k_t, c_t are fixed ratios)
  std::vector<uint16_t> law;    // material-pair index (friction, rolling, law flags)
  std::vector<uint8_t> active;  // contact events: acting within the current step (2: not yet known)
  // History, kept only when `history` is set (friction or rolling resistance somewhere): the
  // committed springs and frame of the last accepted step, and the trial ones of the latest
  // evaluation, which become committed when its step is accepted.
  bool history = false;
  std::vector<double> spring, trial;            // tangential elongation (m)
  std::vector<double> roll, trial_roll;         // rolling spring angle (rad)
  std::vector<contact::ContactFrame> frame, trial_frame;

  int size() const { return static_cast<int>(i.size()); }
  // Takes the sorted candidate pairs; pairs present before keep their committed history.
  void replace(const std::vector<CandidatePair>& fresh);
  // Checkpoints: the pairs, their coefficients and their history, under keys starting with `prefix`.
  void save(Snapshot& s, const std::string& prefix) const;
  void restore(const Snapshot& s, const std::string& prefix);
  void commit() {
    spring.swap(trial);
    roll.swap(trial_roll);
    frame.swap(trial_frame);
  }
};

}  // namespace kiln
