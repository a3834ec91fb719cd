#pragma once
#include "integrators/verlet_family.h"

namespace kiln {

// Basic Stormer-Verlet [thesis-dem-thermal-python.txt, eq. II.16]:
//   x_{n+1} = 2 x_n - x_{n-1} + a_n dt^2,
// started with the Taylor step II.20, x_1 = x_0 + v_0 dt + a_0 dt^2/2, and reporting the central
// difference velocity II.21, v_n = (x_{n+1} - x_{n-1}) / (2 dt). II.21 needs x_{n+1}, so the
// scheme runs one position ahead of the state it reports: after step() the state holds x_n and
// v_n while x_{n+1} is already known.
// Velocity-dependent forces (dashpots, friction) at x_n need v_n before x_{n+1} exists: they see
// the backward difference (x_n - x_{n-1})/dt, an O(dt) estimate, so the scheme is second order
// without dashpots and first order with them. First-order parts z use forward Euler (thesis
// eq. II.11, the explicit temperature update): first order.
class BasicVerlet final : public VerletFamily {
 public:
  void start(OdeSystem& system, double t0, double* y, double dt) override;
  void step() override;

 private:
  void start_without_evaluating(OdeSystem& system, double* y, double dt) override;
  // It runs one position ahead (x_{n+1}) and steps z with the rate at x_n.
  void carried(SnapshotFields& f) override {
    f.field("ahead", ahead_);
    f.field("zrate", zrate_);
  }
  std::vector<double> ahead_;  // x_{n+1}
  std::vector<double> eval_;   // state at which the force is evaluated
  std::vector<double> zrate_;  // dz/dt at x_n
  std::vector<double> z_before_;  // z at the step's start
};

}  // namespace kiln
