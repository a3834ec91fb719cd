// The energy ledger of a run. It closes when
//   kinetic + potential + elastic + dissipated_damping + dissipated_friction
//     - heat_from_dissipation + thermal
//     = (the same at t = 0) + work_by_walls + heat_from_walls,
// and balance_error is the difference, left minus right. `thermal` is sum m c_p T; the part of the
// dissipated energy that became heat in the particles is in both `dissipated_*` and `thermal`,
// so it is subtracted once.
#pragma once

namespace kiln {

struct EnergyLedger {
  double kinetic = 0;    // translational + rotational
  double potential = 0;  // gravity, -sum m g.x
  double elastic = 0;    // normal and tangential springs of active contacts
  double dissipated_damping = 0;
  double dissipated_friction = 0;  // sliding friction, tangential dashpot, rolling resistance
  double work_by_walls = 0;
  double thermal = 0;                // sum of m c_p T (J), thermal scenes
  double heat_from_walls = 0;        // heat that entered through isothermal walls
  double heat_from_dissipation = 0;  // dissipated energy turned into particle heat
  double total() const {
    return kinetic + potential + elastic + dissipated_damping + dissipated_friction - heat_from_dissipation + thermal;
  }
};

// Absolute balance error of `now` against `initial`.
inline double balance_error(const EnergyLedger& initial, const EnergyLedger& now) {
  return now.total() - initial.total() - (now.work_by_walls - initial.work_by_walls) -
         (now.heat_from_walls - initial.heat_from_walls);
}

}  // namespace kiln
