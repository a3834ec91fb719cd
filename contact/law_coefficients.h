// How the law of a pair becomes the coefficients of its contacts: the normal stiffness (from the
// model, for the contact's effective radius), the dashpot (from a damping rate, or from the
// restitution through beta) and whether friction and rolling resistance act. Written once: the
// force loops, the stability estimate and the exact solutions all take their coefficients from here.
#pragma once
#include <cmath>

#include "contact/contact_law.h"
#include "contact/normal_force.h"

namespace kiln::contact {

struct LawCoefficients {
  ContactLaw law;
  double beta = 0;  // c = beta sqrt(m_eff k) from the restitution, unless law.damping_rate > 0
  bool tangential = false, rolling = false;  // friction, rolling resistance present

  // Normal stiffness of a contact of effective radius R* = r_i r_j / (r_i + r_j) (a wall: r_i):
  // N/m (linear) or N/m^1.5 (Hertz).
  double normal_stiffness(double r_eff) const {
    return with_normal_model(law.model, [&](auto m) { return m.stiffness(law, r_eff); });
  }
  // Dashpot of a contact of effective mass m_eff (a wall: m_i) and stiffness k.
  double dashpot(double m_eff, double k) const {
    return law.damping_rate > 0 ? m_eff * law.damping_rate : beta * std::sqrt(m_eff * k);
  }
  NormalLaw normal_law(double m_eff, double r_eff) const {
    const double k = normal_stiffness(r_eff);
    return normal_law_of(k, dashpot(m_eff, k));
  }
  // The law of a contact whose k and c were set when its list was built.
  NormalLaw normal_law_of(double k, double c) const { return {k, c, law.model, law.tension}; }
};

// The coefficients of `law`, its dashpot solved for from its restitution.
LawCoefficients law_coefficients(const ContactLaw& law);

}  // namespace kiln::contact
