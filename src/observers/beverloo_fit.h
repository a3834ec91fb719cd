// Beverloo's law for the discharge rate of a bin through an orifice of width D (case C3):
//   W = C rho_b sqrt(g) (D - k d)^n,
// n = 3/2 for a slot in 2D (W kg/s, rho_b kg/m^2: mass per unit area of the plane), 5/2 for a
// circular orifice in 3D; d the grains' mean diameter, k d the empty annulus at the orifice's rim.
// Beverloo, Leniger and van de Velde, Chem. Eng. Sci. 15 (1961) 260.
#pragma once
#include <vector>

namespace kiln {

struct BeverlooFit {
  double C = 0, k = 0, n = 0;
  double rms_log_residual = 0;  // rms of ln W - ln(fitted W)
};

// C, k and n from rates W[i] at widths D[i] (at least three): for each k, ln W against
// ln(D - k d) is a straight line of slope n; k is the one with the least squared residual
// (scanned over [0, min D / d) and refined by golden section), so the fit is least squares in ln W.
BeverlooFit fit_beverloo(const std::vector<double>& D, const std::vector<double>& W, double rho_b, double g,
                         double d);

// C and k with the exponent fixed at n (at least two widths): W^(1/n) is linear in D, with slope
// (C rho_b sqrt(g))^(1/n) and root D = k d: Beverloo's own way of fitting.
BeverlooFit fit_beverloo_fixed_exponent(const std::vector<double>& D, const std::vector<double>& W, double rho_b,
                                        double g, double d, double n);

}  // namespace kiln
