// Tangential contact force: an incremental spring with a dashpot, limited by Coulomb friction.
// CSIRO [csiro-dem-spring-dashpot.txt]: F_t = min(mu F_n, k_t v_t dt + C v_t). The spring's
// elongation is the contact's history. In 2D the tangent at a contact is the line perp(n), so the
// elongation is a scalar along t = perp(n): it turns with the contact by construction.
// When the trial force exceeds mu F_n the contact slides: the force is capped at mu F_n and the
// spring alone is set to carry it, k_t |s| = mu F_n (as LIGGGHTS does; LAMMPS gran/hooke/history
// also folds the dashpot into the spring, which stores an unphysical c_t v_t/k_t elongation while
// sliding fast). Sticking then resumes without a jump, since the slip speed is zero there.
#pragma once
#include <cmath>

namespace kiln::contact {

struct TangentialLaw {
  double k = 0;   // k_t (N/m)
  double c = 0;   // c_t (N s/m)
  double mu = 0;  // Coulomb coefficient
};

struct TangentialResult {
  double force = 0;   // along t = perp(n), acting on particle i
  double spring = 0;  // new elongation (m)
  bool sliding = false;
  // Power turned into heat over the interval dt: the work of the force on the slip minus what
  // the spring stored, -F_t v_t - (E(spring') - E(spring)) / dt. It includes the dashpot,
  // sliding, and the spring energy cut away by the Coulomb cap, so the ledger closes exactly.
  double dissipation = 0;
};

// `spring` is the committed elongation, `slip_speed` the tangential relative velocity of i with
// respect to j along t, `dt` the time since the elongation was committed (and `inv_dt` its
// reciprocal, 0 when dt = 0: hoisted out of the contact loop), `normal` = F_n >= 0.
inline TangentialResult tangential_force(const TangentialLaw& law, double spring, double slip_speed, double dt,
                                         double inv_dt, double normal) {
  TangentialResult r;
  r.spring = spring + slip_speed * dt;
  r.force = -law.k * r.spring - law.c * slip_speed;
  const double limit = law.mu * (normal > 0 ? normal : 0.0);  // a tensile contact holds no friction
  if (std::abs(r.force) > limit) {
    r.force = std::copysign(limit, r.force);
    r.spring = -r.force / law.k;
    r.sliding = true;
  }
  if (dt > 0) {
    r.dissipation = -r.force * slip_speed - 0.5 * law.k * (r.spring * r.spring - spring * spring) * inv_dt;
  } else {  // at the committed instant itself: the instantaneous rate
    r.dissipation = r.sliding ? -r.force * slip_speed : law.c * slip_speed * slip_speed;
  }
  return r;
}

// Power released when a contact with elongation `spring` opens within dt: its spring energy.
inline double release_dissipation(const TangentialLaw& law, double spring, double dt) {
  return dt > 0 ? 0.5 * law.k * spring * spring / dt : 0.0;
}

inline double tangential_elastic_energy(const TangentialLaw& law, double spring) {
  return 0.5 * law.k * spring * spring;
}

// Constant rolling resistance (Lethe's "constant" model, Ai et al. 2011 model A): a torque of
// magnitude mu_r R* F_n opposing the relative rolling rate omega_i - omega_j; returns the torque
// on particle i (particle j receives the opposite).
inline double rolling_torque(double mu_r, double r_eff, double normal, double relative_spin) {
  if (relative_spin == 0) return 0;
  return -std::copysign(mu_r * r_eff * normal, relative_spin);
}

}  // namespace kiln::contact
