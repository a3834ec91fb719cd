// Heat alone on a frozen contact network: positions and contact forces are fixed, so every
// conductance is a constant and the right-hand side is a sparse graph Laplacian,
//   C_i dT_i/dt = sum_j H_ij (T_j - T_i) + sum_walls H_iw (T_w(t) - T_i).
// This is what makes long heating (minutes at steps of milliseconds or more) feasible where the
// mechanical step would need ~1e9 steps. Its state is only the first-order part z of the full
// state (the ledger, then the temperatures): the integrator is given a pointer into the full
// state vector, so positions stay where they are and nothing is copied.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "integrators/integrator.h"
#include "src/dem/dem_system.h"
#include "thermal/wall_temperature.h"

namespace kiln::thermal {

class FrozenConduction final : public OdeSystem {
 public:
  FrozenConduction(std::vector<ConductanceLink> links, std::vector<double> capacity,
                   std::vector<WallTemperature> walls, int ledger_entries);
  StateLayout layout() const override { return {0, ledger_ + static_cast<int>(inv_capacity_.size())}; }
  void prepare(double, const double*, double) override {}
  void derivative(double t, const double* z, double* zdot) override { conduct(t, z + ledger_, zdot, true); }
  void accept(double) override {}
  // IMEX: all of it is implicit (and linear).
  bool has_implicit_part() const override { return true; }
  void explicit_part(double, const double*, double* zdot) override { std::fill_n(zdot, layout().size(), 0.0); }
  void implicit_part(double t, const double* z, double* zdot) override { derivative(t, z, zdot); }
  void implicit_jacobian_times(double t, const double*, const double* v, double* jv) override {
    conduct(t, v + ledger_, jv, false);
  }
  bool diffusion_jacobian(double t, const double* z, DiffusionJacobian& out) const override;
  std::vector<double> absolute_tolerances(const StepControl& c) const override {
    std::vector<double> atol(layout().size(), c.atol);
    if (std::isfinite(c.atol_temperature)) std::fill(atol.begin() + ledger_, atol.end(), c.atol_temperature);
    return atol;
  }

  // The largest eigenvalue of C^-1 L (1/s), the fastest thermal mode: explicit stepping is stable
  // below reach / it (2 for forward Euler and Heun). Not Gershgorin's bound, up to twice as large.
  double stiffest_rate() const;
  const std::vector<ConductanceLink>& links() const { return links_; }

 private:
  // zdot from the temperatures `temp`; walls at their temperatures, or at 0 for the Jacobian.
  void conduct(double t, const double* temp, double* zdot, bool walls) const;
  std::vector<ConductanceLink> links_;
  std::vector<double> capacity_, inv_capacity_;  // m c_p (J/K) and its inverse (the rates' factor)
  std::vector<WallTemperature> walls_;
  int ledger_;
};

// The network of `system` at (t, y) frozen: its conductances, heat capacities and walls.
FrozenConduction freeze_network(const DemSystem& system, double t, const double* y);

}  // namespace kiln::thermal
