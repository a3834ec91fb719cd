// Candidate contacts in flat arrays (structure of arrays), with their history: the tangential
// and rolling springs and the contact frame they are measured from (contact/contact_frame.h).
// Rebuilt only between steps; a rebuild carries each surviving pair's history over by a merge
// of the two sorted lists (no map, no per-contact allocation).
#pragma once
#include <cstdint>
#include <vector>

#include "contact/contact_frame.h"
#include "src/geometry/broadphase.h"
#include "src/base/snapshot.h"

namespace kiln {

// What one contact did at the latest evaluation, written by that contact alone: threads never
// write the same memory, and each particle then sums the rows it is in, in a fixed order, so
// results do not depend on the number of threads. A contact not touching has a row of zeros.
// Particle j of a pair gets minus the forces and work forces, and torque_j.
struct ContactRow {
  double fx = 0, fy = 0;              // contact force on i (N)
  double torque_i = 0, torque_j = 0;  // contact torques on i and on j (N m)
  double gx = 0, gy = 0;              // friction's work force on i: F_t (n_y, -n_x) (N)
  double dx = 0, dy = 0;              // the dashpot's work force on i: F_dashpot n (N)
};
// Heat rows of a threaded thermal evaluation: the heat that reaches i and j through the contact
// (W), made by its dissipation or (full evaluations) conducted.
struct HeatRow {
  double to_i = 0, to_j = 0;
};

// A list's arrays as raw pointers, taken once per block of contacts by the contact loops: read
// through the vectors, every pointer was loaded again for every contact (the loops' stores of
// doubles might have changed them, for all the compiler knew), and spilled registers with it.
struct ContactArrays {
  const int *i, *j;
  const int *si, *sj;  // their slots
  const double *k, *c;
  const uint16_t* law;
  bool history, rolling;
  const double *spring, *roll;
  const contact::ContactFrame* frame;
  double *trial, *trial_roll;
  contact::ContactFrame* trial_frame;
  // Springs in the state (ContactList::integrated): the slip paths of the state evaluated and of
  // the last accepted step, and where the slip speeds go; null otherwise.
  const double *stage_path, *path;
  double* path_rate;
  // Stick and slip located (ContactList::located): each element's locked mode, and where the
  // evaluation leaves its event function and trial force; null otherwise.
  const int8_t* mode;
  double *margin, *pull;
  // Contact events (ContactList::events): each candidate's `active` (3: pulling, below), and
  // with load events where the evaluation leaves each acting contact's load event function;
  // null otherwise.
  const uint8_t* active;
  double* load_margin;
};

struct ContactList {
  std::vector<int> i, j;        // particle i; particle j (i < j) or segment j
  // The slots of i and j (DemSystem::slot_; a wall list's sj is -1). The list is sorted by its
  // pairs' slots: the lower then the higher (a wall list: i's slot, then the segment).
  std::vector<int> si, sj;
  std::vector<double> k, c;     // normal law coefficients for this pair (k_t, c_t are fixed ratios)
  std::vector<uint16_t> law;    // material-pair index (friction, rolling, law flags)
  // Contact events: acting within the current step (1 pressing, 3 pulling, 2 not yet known, 0
  // not acting). A contact whose law's force (spring and dashpot) turns negative while the bodies
  // still overlap pulls: without tension its force is cut to 0 there, and a cap carries no load.
  // The cut is a kink, located as an event where `load_events` is set (a dashpot somewhere, and
  // no tension or friction located): `load_margin` is each acting contact's event function.
  bool events = false, load_events = false;
  std::vector<uint8_t> active;
  std::vector<double> load_margin;
  // History, kept only when `history` is set (friction or rolling resistance somewhere): the
  // committed springs and frame of the last accepted step, and the trial ones of the latest
  // evaluation, which become committed when its step is accepted.
  bool history = false;
  bool rolling = false;                         // some law has rolling resistance: rolling springs
  std::vector<double> spring, trial;            // tangential elongation (m)
  std::vector<double> roll, trial_roll;         // rolling spring angle (rad), only with `rolling`
  std::vector<contact::ContactFrame> frame, trial_frame;
  // Springs in the state (DemSystem::integrate_history): each candidate's slip path, the integral
  // of its slip speed since the lists were built (0 while it does not act), is a component of the
  // state that the integrator advances at every stage. A spring's trial elongation is then its
  // committed one plus the path since the last accepted step, `path` (its value there) and
  // `trial_path` (the latest evaluation's), instead of the displacement between contact frames.
  bool integrated = false;
  std::vector<double> path, trial_path;
  const double* stage_path = nullptr;  // the latest evaluation's state and rates, at this list's paths
  double* path_rate = nullptr;
  // Stick and slip located (contact events on lists with history, contact/stick_slip.h): two
  // capped elements per candidate, its tangential spring at 2p and its rolling spring at 2p + 1,
  // each with its mode locked for the step (0 sticks, +-1 slips with force +-limit), and from the
  // latest evaluation their event functions and trial forces (-k s - c v: the sign a slip takes).
  bool located = false;
  std::vector<int8_t> mode;
  std::vector<double> margin, pull;

  // Rows of the latest threaded evaluation (one per candidate; empty until one runs) and heat rows
  // of the latest thermal one, and where the particle at each slot k finds its rows: those where
  // its slot is the pair's lower one are the range [by_i[k], by_i[k + 1]) (the list is sorted by
  // it); for a particle list, those where it is the higher are by_j_rows[by_j[k] .. by_j[k + 1]),
  // in ascending order.
  std::vector<ContactRow> rows;
  std::vector<HeatRow> heat_rows;
  // Each candidate's conductance (W/K, 0 when not touching) at the latest full thermal evaluation:
  // conduction's Jacobian at that state without the geometry again. Apart from the heat rows, which
  // one thread never stores: the Jacobian reads 8 bytes per candidate, not a row of 24.
  std::vector<double> conductance;
  std::vector<int> by_i, by_j, by_j_rows;

  int size() const { return static_cast<int>(i.size()); }
  ContactArrays arrays() {
    return {i.data(),      j.data(),      si.data(),     sj.data(),     k.data(),          c.data(),
            law.data(),    history,       rolling,       spring.data(), roll.data(),       frame.data(),
            trial.data(),  trial_roll.data(), trial_frame.data(), stage_path, path.data(), path_rate,
            located ? mode.data() : nullptr, margin.data(), pull.data(),
            events ? active.data() : nullptr, load_events ? load_margin.data() : nullptr};
  }
  // Takes the candidates of `particles` particles as the broadphase found them among the places
  // in slot order: pairs of slots (a < b), or (slot, segment), sorted. `at[s]` is the particle at
  // slot s, `slot` its inverse. Pairs present before keep their committed history, also when the
  // slots changed since (the kept list is then walked in the new slots' order).
  // `pairs`: j is a particle (indexed by_j too), not a wall segment.
  void replace(const std::vector<CandidatePair>& fresh, int particles, bool pairs, const int* at, const int* slot);
  // si and sj from i and j (after restore(), with the slots it restored).
  void place(const int* slot, bool pairs);
  // Sizes the rows and finds each slot's rows (after replace() or restore()).
  void index(int particles, bool pairs);
  // Checkpoints: the pairs, their coefficients and their history.
  void state(SnapshotFields& f);
  std::vector<int8_t> scratch_mode;
  std::vector<uint8_t> scratch_active;  // replace()'s and index()'s, kept: no allocation per rebuild
  std::vector<int> scratch_next, scratch_walk;
  std::vector<uint64_t> scratch_keys;
  void commit() {
    spring.swap(trial);
    roll.swap(trial_roll);
    frame.swap(trial_frame);
    path.swap(trial_path);
  }
};

}  // namespace kiln
