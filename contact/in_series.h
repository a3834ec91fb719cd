// a b / (a + b) for a, b > 0: two springs in series, two bodies' effective mass, radius or
// inertia. Written as the product over the sum, which every run's contacts have used (the same
// bits); as 1 / (1/a + 1/b) where the product overflows or underflows: two discs of 1e-250 kg/m^3
// (masses near 1e-259 kg) had an effective mass of 0, and the rolling stiffness
// I_spin k_n / (16 m_eff) was NaN (issue 28's review); two stiffnesses of 1e-200 N/m combined to 0.
#pragma once
#include <cfloat>
#include <cmath>

namespace kiln::contact {

inline double in_series(double a, double b) {
  const double product = a * b;
  return std::isfinite(product) && product >= DBL_MIN ? product / (a + b) : 1 / (1 / a + 1 / b);
}

}  // namespace kiln::contact
