#include "contact/law_coefficients.h"

namespace kiln::contact {

LawCoefficients law_coefficients(const ContactLaw& law) {
  LawCoefficients f;
  f.law = law;
  f.beta = law.damping_rate > 0 ? 0 : restitution_damping(law.restitution, law.model, law.tension);
  f.tangential = law.friction > 0;
  f.rolling = law.rolling_friction > 0;
  return f;
}

}  // namespace kiln::contact
