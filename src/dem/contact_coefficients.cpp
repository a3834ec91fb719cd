#include "src/dem/contact_coefficients.h"

namespace kiln {

ContactCoefficients contact_coefficients(const Scene& scene, int a, int b) {
  const PairLaw& law = scene.law(a, b);
  ContactCoefficients f;
  f.hertz = law.model == NormalModel::hertz;
  f.tension = law.tension;
  f.stiffness = law.stiffness;
  f.effective_modulus = law.effective_modulus;
  f.damping_rate = law.damping_rate;
  f.beta = law.damping_rate > 0 ? 0 : contact::restitution_damping(law.restitution, f.hertz, f.tension);
  f.mu = law.friction;
  f.mu_roll = law.rolling_friction;
  f.tangential = law.friction > 0;
  f.rolling = law.rolling_friction > 0;
  f.kt_ratio = law.tangential_stiffness_ratio;
  f.ct_ratio = law.tangential_damping_ratio;
  f.rolling_model = law.rolling_model;
  f.eta_roll = law.rolling_damping_ratio;
  const Material &ma = scene.materials[a], &mb = scene.materials[b];
  f.conduction = {law.conduction, ma.conductivity, mb.conductivity, law.conductance, law.modulus_ratio,
                  law.effective_modulus, scene.thickness, law.contact_resistance};
  if (ma.conductivity > 0 && mb.conductivity > 0)
    f.heat_share = thermal::heat_partition(ma.electrical_resistivity, mb.electrical_resistivity, ma.conductivity,
                                           mb.conductivity);
  return f;
}

}  // namespace kiln
