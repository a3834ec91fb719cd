// The energy ledger of a run. It closes when
//   kinetic + potential + elastic + dissipated_damping + dissipated_friction
//     = (the same at t = 0) + work_by_walls,
// and balance_error is the difference, left minus right.
#pragma once

namespace kiln {

struct EnergyLedger {
  double kinetic = 0;    // translational + rotational
  double potential = 0;  // gravity, -sum m g.x
  double elastic = 0;    // normal and tangential springs of active contacts
  double dissipated_damping = 0;
  double dissipated_friction = 0;  // sliding friction, tangential dashpot, rolling resistance
  double work_by_walls = 0;
  double total() const { return kinetic + potential + elastic + dissipated_damping + dissipated_friction; }
};

// Absolute balance error of `now` against `initial`.
inline double balance_error(const EnergyLedger& initial, const EnergyLedger& now) {
  return now.total() - initial.total() - (now.work_by_walls - initial.work_by_walls);
}

}  // namespace kiln
