// The checks that stop an unstable run. A failure throws InstabilityError naming the check, the
// time, the step and the step the stability estimate recommends. What the checks measured on the
// way (how close the ledger came to the blow-up threshold, the largest bounded overshoot of the
// maximum principle) is a figure of the run: figures(), summary.json's "checks".
#pragma once
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "src/dem/dem_system.h"
#include "src/dem/energy.h"
#include "src/scene/scene.h"
#include "src/base/snapshot.h"
#include "src/run/stability.h"

namespace kiln {

// Fewer steps than this per contact duration and a contact's onset and release fall inside steps
// with errors of the order of the step: a run the energy check stops below the stability limit is
// told that this, not a linear mode, may be what made the energy. At the tables' limits a contact
// lasts 0.6 to 1.6 steps (pi / (omega dt), omega dt from 2 to 5); at the recommended dt it lasts 50.
inline constexpr double under_resolved_contact = 10;

class StabilityGuard {
 public:
  // `estimate`: the scene's (estimate_stability(scene), which run_scene makes before the run).
  StabilityGuard(const Scene& scene, const DemSystem& sys, const EnergyLedger& initial,
                 const StabilityEstimate& estimate);
  // After every mechanical step of length h ending in state y: the largest overlap against
  // checks.max_overlap_fraction, and the largest displacement in a step against the particle's
  // radius (a particle that moves more than its radius in one step can pass through a wall or
  // another particle between two evaluations, unseen).
  void every_step(double t, const double* y, double h);
  // At frames and every 64 steps: a finite state, and the energy check on the state's ledger.
  void finite(double t, const double* y, int size);
  // After every step of a thermal scene: temperatures within the maximum principle of conduction
  // (an excursion beyond the range by more than a tenth of its width that grows from one step to
  // the next, or is there at the run's last step, stops the run; any other is a bounded
  // overshoot, recorded). With heat sources only the lower bound holds.
  void temperatures(double t, const double* y);
  // Energy blow-up: the ledger is off, either way, by more than a quarter of the largest energy
  // exchanged so far, beyond what rounding the positions to their ulp at every step accounts for.
  void energy(double t, const double* y, const EnergyLedger& now);
  const StabilityEstimate& estimate() const { return estimate_; }
  // What the checks measured over the run, for summary.json's "checks".
  nlohmann::json figures() const;
  // Checkpoints: what the checks have measured so far.
  void state(SnapshotFields& f);
  // The stage now running, for the message: its step, and for a stage of heat alone the explicit
  // conduction limit of its network (NaN for the mechanical stage).
  void set_stage(double dt, double heat_limit = NAN) {
    dt_ = dt;
    heat_limit_ = heat_limit;
  }

 private:
  // Throws InstabilityError: the check, the time, the step, and the step recommended by the
  // estimate at the start joined with the limit on the contacts of the state y now. `made_energy`:
  // the energy check fired, which under-resolved contacts can trip below the limit.
  [[noreturn]] void fail(double t, const double* y, const std::string& what, bool made_energy = false) const;
  const Scene& scene_;
  const DemSystem& sys_;
  EnergyLedger initial_;
  StabilityEstimate estimate_;
  double dt_ = 0;
  double heat_limit_ = NAN;
  // Energy: the largest exchanged() seen, the worst |balance error| / that so far, and the
  // potential energy of rounding every position once (J) times the mechanical steps taken.
  double largest_exchange_ = 0;
  double rounding_per_step_ = 0;
  long steps_ = 0;
  double worst_relative_error_ = 0, worst_error_time_ = 0;
  // Maximum principle: the range of the initial and wall temperatures (high_ infinite with heat
  // sources) and its width (1 K when all start equal), the largest excursion beyond it so far,
  // and the excursion at the previous check.
  double low_ = 0, high_ = 0, width_ = 1;
  double overshoot_ = 0, overshoot_time_ = 0, previous_excursion_ = 0;
  int overshoot_particle_ = -1;
};

}  // namespace kiln
