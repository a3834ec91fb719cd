// Contact conductance laws: pure functions of the contact geometry, the normal force and the
// materials. H is the heat flow per kelvin through one contact (W/K); a wall is a flat body
// (r_j = infinity).
#pragma once
#include <cmath>

namespace kiln::thermal {

enum class ConductionModel { none, lens, hertz, batchelor_obrien, pipe_network, constant };

// Harmonic mean of two conductivities, 2 k1 k2 / (k1 + k2): k itself for one material.
inline double harmonic_mean(double k1, double k2) { return 2 * k1 * k2 / (k1 + k2); }

// Half chord of the lens where two circles overlap ([thesis-dem-thermal-python.txt] Figure II.3
// and Annex A): AE = (r_i^2 - r_j^2 + d^2) / (2d), r_c = sqrt(r_i^2 - AE^2). Against a flat wall at
// distance d from the centre: r_c = sqrt(r_i^2 - d^2).
inline double lens_radius(double ri, double rj, double d) {
  const double ae = std::isinf(rj) ? d : (ri * ri - rj * rj + d * d) / (2 * d);
  const double c2 = ri * ri - ae * ae;
  return c2 > 0 ? std::sqrt(c2) : 0.0;
}

// [thesis] eq. II.5: H = 2 k r_c, k the harmonic mean conductivity for unlike materials.
inline double lens_conductance(double k_mean, double r_c) { return 2 * k_mean * r_c; }

// Batchelor & O'Brien as LIGGGHTS' heat/gran/conduction and MFiX use it:
// H = 4 k1 k2 / (k1 + k2) sqrt(A / pi), A = pi r_c^2 the contact area, so H = 2 k_mean r_c (the
// lens law) times an optional correction for a softened Young's modulus: a Hertz contact radius
// goes as E^(-1/3) at a given force, so r_c,real = r_c (E_sim / E_real)^(1/3).
// (Without a correction the cube root, a fifth of a thermal contact's cost, is skipped: cbrt(1) = 1.)
inline double batchelor_obrien_conductance(double k_mean, double r_c, double e_sim_over_real) {
  const double lens = lens_conductance(k_mean, r_c);
  return e_sim_over_real == 1 ? lens : lens * std::cbrt(e_sim_over_real);
}

// Nguyen et al. 2009 [nguyen2009-friction-heat-dem.txt] from Hertz theory:
// H = 2 lambda (3 F_n a* / (4 E*))^(1/3), 1/a* = 1/a_i + 1/a_j (a* = a_i against a wall).
inline double hertz_conductance(double k_mean, double normal_force, double a_star, double e_star) {
  return normal_force > 0 ? 2 * k_mean * std::cbrt(3 * normal_force * a_star / (4 * e_star)) : 0.0;
}

// Feng's pipe network [fdem-contact-heat-transfer.txt], for cylinders of thickness t: the
// resistance of one disc per unit length, R_A = (1/(pi k_A)) (-ln alpha_A + 3/2 + alpha_A^2/36)
// with alpha_A the half angle of the contact arc (sin alpha_A = r_c / r_A), accurate below 30
// degrees; R_AB = R_A + R_B + R_c per unit length, H = t / R_AB. A wall adds no resistance of
// its own (its temperature is its surface's).
inline double pipe_resistance(double k, double r, double r_c) {
  const double alpha = std::asin(std::fmin(1.0, r_c / r));
  return (-std::log(alpha) + 1.5 + alpha * alpha / 36) / (M_PI * k);
}
inline double pipe_network_conductance(double ra, double ka, double rb, double kb, double r_c, double thickness,
                                       double contact_resistance) {
  if (r_c <= 0) return 0;
  const double r_b = std::isinf(rb) ? 0.0 : pipe_resistance(kb, rb, r_c);
  return thickness / (pipe_resistance(ka, ra, r_c) + r_b + contact_resistance);
}

// Share of frictional heat that goes to particle i (Nguyen et al. 2009, section 3.2, after Mokrani and
// Bourouga 2005): beta = (rho_i/(rho_i + rho_j) + lambda_i/(lambda_i + lambda_j)) / 2, with rho the
// electrical resistivities and lambda the conductivities; 1/2 for one material. The formula is
// the mean of two estimates of the share, one from each property. When the resistivities are not
// both given, the electrical estimate is unknown and the thermal one stands alone:
// beta = lambda_i / (lambda_i + lambda_j) (averaging it with an assumed 1/2 would invent a value).
inline double heat_partition(double resistivity_i, double resistivity_j, double k_i, double k_j) {
  const double thermal = k_i / (k_i + k_j);
  if (resistivity_i > 0 && resistivity_j > 0) return 0.5 * (resistivity_i / (resistivity_i + resistivity_j) + thermal);
  return thermal;
}

// One contact's conduction law with the constants of its two materials.
struct ConductionLaw {
  ConductionModel model = ConductionModel::none;
  double k_i = 0, k_j = 0;          // conductivities of the two bodies (j: the wall's for walls)
  double constant = 0;              // constant model: H
  double modulus_ratio = 1;         // batchelor_obrien: E_simulated / E_real
  double e_star = 0;                // hertz: effective modulus
  double thickness = 0;             // pipe_network: cylinder thickness
  double contact_resistance = 0;    // pipe_network: R_c per unit length
};

// H of a contact between discs of radii r_i and r_j (r_j infinite for a wall) whose centres are
// d apart (for a wall: the centre's distance to it), pressed with normal force F_n; k_mean is
// harmonic_mean(law.k_i, law.k_j), which a contact loop takes once per pair of materials (its
// division was a tenth of a thermal contact's cost).
// (Always inlined: in a contact loop, a call's spills cost as much as the lens law itself.)
[[gnu::always_inline]] inline double conductance(const ConductionLaw& law, double k_mean, double ri, double rj,
                                                 double d, double normal_force) {
  switch (law.model) {
    case ConductionModel::none:
      return 0;
    case ConductionModel::constant:
      return law.constant;
    case ConductionModel::lens:
      return lens_conductance(k_mean, lens_radius(ri, rj, d));
    case ConductionModel::batchelor_obrien:
      return batchelor_obrien_conductance(k_mean, lens_radius(ri, rj, d), law.modulus_ratio);
    case ConductionModel::hertz:
      return hertz_conductance(k_mean, normal_force,
                               std::isinf(rj) ? ri : ri * rj / (ri + rj), law.e_star);
    case ConductionModel::pipe_network:
      return pipe_network_conductance(ri, law.k_i, rj, law.k_j, lens_radius(ri, rj, d), law.thickness,
                                      law.contact_resistance);
  }
  return 0;
}
// The same, the mean conductivity taken here (for callers outside a contact loop).
inline double conductance(const ConductionLaw& law, double ri, double rj, double d, double normal_force) {
  return conductance(law, harmonic_mean(law.k_i, law.k_j), ri, rj, d, normal_force);
}

}  // namespace kiln::thermal
