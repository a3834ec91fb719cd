#include "src/dem/contact_coefficients.h"

namespace kiln {

ContactCoefficients contact_coefficients(const Scene& scene, int a, int b) {
  const PairLaw& law = scene.law(a, b);
  const Material &ma = scene.materials[a], &mb = scene.materials[b];
  const thermal::ConductionParams& h = law.conduction;
  const thermal::ConductionLaw conduction{h.model,         ma.conductivity,
                                          mb.conductivity, h.conductance,
                                          h.modulus_ratio, law.contact.effective_modulus,
                                          scene.thickness, h.contact_resistance};
  const double heat_share = ma.conductivity > 0 && mb.conductivity > 0
                                ? thermal::heat_partition(ma.electrical_resistivity, mb.electrical_resistivity,
                                                          ma.conductivity, mb.conductivity)
                                : 0.5;
  return {contact::law_coefficients(law.contact), conduction, heat_share,
          ma.conductivity + mb.conductivity > 0 ? thermal::harmonic_mean(ma.conductivity, mb.conductivity) : 0.0};
}

}  // namespace kiln
