// Rolling resistance: a torque against the relative rotation omega_r = omega_i - omega_o of the
// two bodies at a contact, at most M_max = mu_r R* F_n (mu_r the rolling friction coefficient,
// R* the effective radius, F_n >= 0 the normal force).
//
// Both models share one form, an elastic-plastic rolling spring with a dashpot (Ai, Chen, Rotter
// and Ooi, "Assessment of rolling resistance models in discrete element simulations", Powder
// Technology 206 (2011) 269-282, model C, the elastic-plastic spring-dashpot): M = -k_r psi - c_r omega_r, capped at
// M_max; at the cap the torque is M_max and the spring is shortened to at most M_max / k_r
// (contact/capped_spring.h, as for friction: the cap never lengthens it).
// psi, the rolling spring's angle, is the relative rotation since the contact began, measured
// from the frame of the last accepted step (contact/contact_frame.h), so it is a function of the
// state and every stage of a multi-stage method sees its own.
//  - epsd: k_r = 2.25 k_n mu_r^2 R*^2 (Ai et al.'s choice, also LIGGGHTS' epsd; k_n the
//    linear(ised) normal stiffness), c_r = eta_r 2 sqrt(I_r k_r) with
//    1/I_r = 1/(I_i + m_i r_i^2) + 1/(I_j + m_j r_j^2) (a wall adds nothing), eta_r the scene's
//    rolling_damping_ratio (Ai et al. used 0.3, the default).
//  - constant: Ai et al.'s model A (the constant directional torque, Lethe's "constant", LIGGGHTS'
//    cdt): M = -M_max sign(omega_r) while the contact rolls. A bare sign function has no rest
//    state: the relative spin parks at +-(M_max dt / I) and a disc below its rolling angle creeps
//    at a speed proportional to dt. Here the rest state is held by a stiff spring: alone on the
//    bodies' relative rotation (inertia I_s = 1/(1/I_i + 1/I_j)) it would ring at a quarter of the
//    normal contact's frequency (k_r = I_s k_n / (16 m_eff)), critically damped
//    (c_r = 2 sqrt(I_s k_r)); while the contact rolls the torque is exactly the constant M_max.
#pragma once
#include <cmath>

#include "contact/capped_spring.h"

namespace kiln::contact {

enum class RollingModel { constant, epsd };

struct RollingLaw {
  double k = 0;      // k_r (N m/rad)
  double c = 0;      // c_r (N m s/rad)
  double limit = 0;  // M_max = mu_r R* F_n (N m), F_n the cap's load (contact/normal_force.h cap_load)
};

// k_r and c_r of a contact. `k_normal`: the linear(ised) normal stiffness (N/m); `r_eff`: R*;
// `inertia_r`: I_r (kg m^2); `spin_inertia`: the inertia of the bodies' relative rotation,
// 1/(1/I_i + 1/I_j) (a wall: I_i); `m_eff`: the effective mass (kg); `eta`: the epsd damping ratio;
// `load`: the normal load carrying the cap (N), cap_load's (negative only in the stages of a
// located contact that overshoot its pull's start or its release).
inline RollingLaw rolling_law(RollingModel model, double mu_r, double k_normal, double r_eff, double inertia_r,
                              double spin_inertia, double m_eff, double eta, double load) {
  RollingLaw law;
  law.limit = mu_r * r_eff * load;
  if (model == RollingModel::epsd) {
    law.k = 2.25 * k_normal * mu_r * mu_r * r_eff * r_eff;
    law.c = eta * 2 * std::sqrt(inertia_r * law.k);
  } else {
    law.k = spin_inertia * k_normal / (16 * m_eff);
    law.c = 2 * std::sqrt(spin_inertia * law.k);
  }
  return law;
}

struct RollingResult {
  double torque = 0;  // on particle i (the other body receives the opposite) (N m)
  double spring = 0;  // rolling spring angle after the cap (rad)
  bool rolling = false;  // at the cap: the contact rolls
};

// `angle`: the trial spring angle psi of this state (rad); `relative_spin`: omega_r (rad/s).
inline RollingResult rolling_torque(const RollingLaw& law, double angle, double relative_spin) {
  const CappedSpringResult e = capped_spring(law.k, law.c, law.limit, angle, relative_spin);
  return {e.force, e.spring, e.slipping};
}

inline double rolling_elastic_energy(const RollingLaw& law, double angle) { return 0.5 * law.k * angle * angle; }

}  // namespace kiln::contact
