// The coefficients of the contacts between two materials of the scene: the mechanics of their
// contact law (contact/law_coefficients.h: stiffness, dashpot, friction and rolling resistance),
// the conduction law with the two materials' constants, and the share of frictional heat. The
// force loops, the stability estimate and the exact solutions all take their coefficients from here.
#pragma once

#include "contact/law_coefficients.h"
#include "src/scene/scene.h"
#include "thermal/conductance.h"

namespace kiln {

struct ContactCoefficients : contact::LawCoefficients {
  thermal::ConductionLaw conduction;  // from the first material to the second
  double heat_share = 0.5;            // share of frictional heat for the first material's body
  // harmonic_mean(conduction.k_i, conduction.k_j) (W/(m K)); 0, not 0/0, between two materials that
  // do not conduct (the scene reader allows no conduction law between them).
  double mean_conductivity = 0;
};

// The coefficients of the law between materials a and b of the scene.
ContactCoefficients contact_coefficients(const Scene& scene, int a, int b);

}  // namespace kiln
