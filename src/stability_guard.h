// The checks that stop an unstable run. A failure throws InstabilityError naming the check, the
// time, the step and the step the stability estimate recommends.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "src/dem_system.h"
#include "src/energy.h"
#include "src/scene.h"
#include "src/stability.h"

namespace kiln {

class StabilityGuard {
 public:
  StabilityGuard(const Scene& scene, const DemSystem& sys, const EnergyLedger& initial);
  // After every mechanical step: the largest overlap against checks.max_overlap_fraction.
  void every_step(double t) const;
  // A finite state, and temperatures within the maximum principle of conduction.
  void finite(double t, const double* y, int size) const;
  // Energy blow-up: the ledger's error exceeds a quarter of all the energy that has changed form.
  void energy(double t, const EnergyLedger& now) const;
  const StabilityEstimate& estimate() const { return estimate_; }
  // What the checks measured over the run, for summary.json's "checks".
  nlohmann::json figures() const;
  // The stage now running: its step and whether only heat is integrated (for the message).
  void set_stage(double dt, bool heat_only) {
    dt_ = dt;
    heat_only_ = heat_only;
  }

 private:
  [[noreturn]] void fail(double t, const std::string& what) const;
  const Scene& scene_;
  const DemSystem& sys_;
  EnergyLedger initial_;
  StabilityEstimate estimate_;
  double low_ = 0, high_ = 0;
  double dt_ = 0;
  bool heat_only_ = false;
};

}  // namespace kiln
