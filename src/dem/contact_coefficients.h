// How the law chosen for a pair of materials becomes the coefficients of one contact: the normal
// stiffness (linear k, or Hertz k = 4/3 E* sqrt(R*)), the dashpot (from a damping rate, or from
// the restitution through beta), the tangential and rolling scalings, the conduction law and the
// share of frictional heat. Written once: the force loops, the stability estimate and the exact
// solutions all take their coefficients from here.
#pragma once
#include <cmath>

#include "contact/normal_force.h"
#include "contact/rolling_resistance.h"
#include "src/scene/scene.h"
#include "thermal/conductance.h"

namespace kiln {

struct ContactCoefficients {
  bool hertz = false, tension = true;
  bool tangential = false, rolling = false;  // friction, rolling resistance present
  double stiffness = 0;          // linear: k (N/m)
  double effective_modulus = 0;  // Hertz: E* (Pa)
  double damping_rate = 0;       // linear dashpot from a rate: c = m_eff gamma_n (1/s); 0: from beta
  double beta = 0;               // otherwise c = beta sqrt(m_eff k), beta from the restitution
  double mu = 0, mu_roll = 0;
  double kt_ratio = 0, ct_ratio = 0;  // k_t = kt_ratio k_n (Hertz: of 3/2 k delta^1/2), c_t = ct_ratio c
  contact::RollingModel rolling_model = contact::RollingModel::constant;
  double eta_roll = 0;                // epsd damping ratio
  thermal::ConductionLaw conduction;  // from the first material to the second
  double heat_share = 0.5;            // share of frictional heat for the first material's body

  // Normal stiffness of a contact of effective radius R* = r_i r_j / (r_i + r_j) (a wall: r_i):
  // N/m (linear) or N/m^1.5 (Hertz).
  double normal_stiffness(double r_eff) const {
    return hertz ? 4.0 / 3.0 * effective_modulus * std::sqrt(r_eff) : stiffness;
  }
  // Dashpot of a contact of effective mass m_eff (a wall: m_i) and stiffness k.
  double dashpot(double m_eff, double k) const { return damping_rate > 0 ? m_eff * damping_rate : beta * std::sqrt(m_eff * k); }
  contact::NormalLaw normal_law(double m_eff, double r_eff) const {
    const double k = normal_stiffness(r_eff);
    return {k, dashpot(m_eff, k), hertz, tension};
  }
};

// The coefficients of the law between materials a and b of the scene.
ContactCoefficients contact_coefficients(const Scene& scene, int a, int b);

}  // namespace kiln
