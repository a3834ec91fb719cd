// The contact law of a pair of materials: its parameters, and the rules that give an unlisted pair
// its law from the constants of its two materials. The normal models are the springs of
// contact/linear_spring.h and contact/hertz_spring.h, dispatched in contact/normal_force.h; which
// keys of a scene's `contacts:` entry each model reads is contact/model_table.h.
#pragma once

#include "contact/rolling_resistance.h"

namespace kiln::contact {

enum class NormalModel { linear, hertz };

// What one material brings to the laws of its contacts.
struct ContactMaterial {
  double youngs_modulus = 0;    // Pa; needed by Hertz contacts and the Rayleigh estimate
  double poisson_ratio = 0.3;
  double stiffness = 0;         // N/m, linear normal spring
  double restitution = 1;       // normal coefficient of restitution in (0, 1]
  double friction = 0;          // Coulomb coefficient
  double rolling_friction = 0;  // rolling resistance coefficient mu_r
};

// Contact law parameters for one unordered pair of materials.
struct ContactLaw {
  NormalModel model = NormalModel::linear;
  double stiffness = 0;          // linear: k (N/m)
  double effective_modulus = 0;  // Hertz: E* with 1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2
  double restitution = 1;        // used unless damping_rate > 0
  double damping_rate = 0;       // gamma_n (1/s): linear dashpot c = m_eff gamma_n
  bool tension = true;           // false: the normal force is clamped at zero (no attraction)
  double friction = 0;
  double tangential_stiffness_ratio = 2.0 / 7.0;  // k_t / k_n
  double tangential_damping_ratio = 0.5;          // c_t / c_n
  double rolling_friction = 0;
  RollingModel rolling_model = RollingModel::constant;
  double rolling_damping_ratio = 0.3;  // epsd: eta_r
};

// E* of two materials, 1/E* = (1-nu_a^2)/E_a + (1-nu_b^2)/E_b; 0 unless both give a modulus.
double effective_modulus(const ContactMaterial& a, const ContactMaterial& b);

// Default law of an unlisted pair: springs in series scaled to give k for like materials
// (2 k1 k2 / (k1 + k2)), the geometric mean of the restitutions, the smaller friction.
ContactLaw mixed_law(const ContactMaterial& a, const ContactMaterial& b, NormalModel model);

}  // namespace kiln::contact
