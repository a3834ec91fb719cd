// Tangential contact force: a spring with a dashpot, limited by Coulomb friction.
// CSIRO [csiro-dem-spring-dashpot.txt]: F_t = min(mu F_n, k_t xi + c_t v_t), xi the tangential
// elongation (the contact's history). In 2D the tangent at a contact is t = perp(n), so the
// elongation is a scalar along t: it turns with the contact by construction.
//
// The elongation is a function of the state, not of the step: it is the elongation at the last
// accepted step plus the relative tangential displacement of the two contact points since then
// (contact/contact_frame.h), then the Coulomb cap. So every stage of a multi-stage method sees
// the elongation that belongs to its own state, and a method keeps its order in stick (an
// increment v_t dt from one slip rate per step would be a rectangle rule: first order).
//
// When the trial force exceeds mu F_n the contact slides: the force is capped at mu F_n and the
// spring shortened to at most mu F_n / k_t (contact/capped_spring.h: the cap never lengthens it,
// so the spring stores no energy the friction force did not put in). LAMMPS gran/hooke/history
// instead folds the dashpot into the spring, which stores an unphysical c_t v_t / k_t elongation
// while sliding fast.
#pragma once
#include <cmath>

#include "contact/capped_spring.h"
#include "contact/normal_force.h"

namespace kiln::contact {

struct TangentialLaw {
  double k = 0;   // k_t (N/m)
  double c = 0;   // c_t (N s/m)
  double mu = 0;  // Coulomb coefficient
};

struct TangentialResult {
  double force = 0;   // along t = perp(n), acting on particle i (N)
  double spring = 0;  // elongation after the Coulomb cap (m)
  bool sliding = false;
};

// The law of a contact whose normal law is `normal` at `overlap`: the tangential spring scales
// with the normal spring's slope, its dashpot as the normal dashpot (ratios of the pair's law).
[[gnu::always_inline]] inline TangentialLaw tangential_law(const NormalLaw& normal, double overlap, double stiffness_ratio,
                                                           double damping_ratio, double friction) {
  return {stiffness_ratio * stiffness_slope(normal, overlap), damping_ratio * normal.c * dashpot_scale(normal, overlap),
          friction};
}

// `elongation`: the trial elongation of this state (m); `slip_speed`: the tangential relative
// velocity of i's contact point against the other body's, along t (m/s); `normal` = F_n (N): a
// tensile contact (F_n <= 0) holds no friction.
[[gnu::always_inline]] inline TangentialResult tangential_force(const TangentialLaw& law, double elongation, double slip_speed,
                                         double normal) {
  const CappedSpringResult e = capped_spring(law.k, law.c, law.mu * (normal > 0 ? normal : 0.0), elongation, slip_speed);
  return {e.force, e.spring, e.slipping};
}

inline double tangential_elastic_energy(const TangentialLaw& law, double spring) {
  return 0.5 * law.k * spring * spring;
}

}  // namespace kiln::contact
