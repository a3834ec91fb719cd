#include "contact/contact_law.h"

#include "contact/in_series.h"

#include <algorithm>
#include <cmath>

namespace kiln::contact {

double effective_modulus(const ContactMaterial& a, const ContactMaterial& b) {
  if (a.youngs_modulus <= 0 || b.youngs_modulus <= 0) return 0;
  return 1.0 / ((1 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus +
                (1 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus);
}

ContactLaw mixed_law(const ContactMaterial& a, const ContactMaterial& b, NormalModel model) {
  ContactLaw law;
  law.model = model;
  // Springs in series (contact/in_series.h: two stiffnesses of 1e300 made an infinite pair
  // stiffness, which the step estimate left out; two of 1e-200 made 0).
  law.stiffness = !(a.stiffness > 0 && b.stiffness > 0) ? std::max(a.stiffness, b.stiffness)
                                                        : 2 * in_series(a.stiffness, b.stiffness);
  law.effective_modulus = effective_modulus(a, b);
  law.restitution = std::sqrt(a.restitution * b.restitution);
  law.friction = std::min(a.friction, b.friction);
  law.rolling_friction = std::min(a.rolling_friction, b.rolling_friction);
  return law;
}

}  // namespace kiln::contact
