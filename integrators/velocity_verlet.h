#pragma once
#include "integrators/verlet_family.h"

namespace kiln {

// Velocity Verlet [thesis-dem-thermal-python.txt, eqs. II.25-II.27]:
//   v_{n+1/2} = v_n + a_n dt/2;  x_{n+1} = x_n + v_{n+1/2} dt;  a_{n+1} = A(x_{n+1}, v*);
//   v_{n+1} = v_{n+1/2} + a_{n+1} dt/2.
// II.27 assumes a depends on x only. With dashpots and friction the force also needs a velocity
// v* at t_{n+1}, which is not known yet. Two choices, both one force evaluation per step:
//  - `velocity-verlet` uses v* = v_{n+1/2}, as LAMMPS and LIGGGHTS do: an O(dt) error in the
//    damping force, so the scheme is first order with dashpots (second order without);
//  - `velocity-verlet-predicted` uses v* = v_n + a_n dt, an O(dt^2) prediction of v_{n+1}: second
//    order with dashpots. Without velocity-dependent forces both are the same scheme.
// First-order parts z use Heun's method (Euler predictor, trapezoidal corrector): second order.
class VelocityVerlet final : public VerletFamily {
 public:
  explicit VelocityVerlet(bool predicted_velocity) : predicted_(predicted_velocity) {}
  void start(OdeSystem& system, double t0, double* y, double dt) override;
  void step() override;

 private:
  void start_without_evaluating(OdeSystem& system, double* y, double dt) override;
  // Nothing carried beyond the shared state: v_{n+1/2} and the z scratch are rebuilt every step.
  bool predicted_;
  std::vector<double> v_half_;
  std::vector<double> z_old_, zrate_old_;
  bool slope_correction_ = false;  // z has a stiff linear part whose slope is moved to z_{n+1}
  std::vector<double> dz_, jdz_;   // z_{n+1} - z* (laid out as the state) and J times it
  std::vector<double> z_unbooked_;  // z before the works and the contacts' heat are booked
};

}  // namespace kiln
