#include "src/observers/beverloo_fit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kiln {

namespace {

struct Line {
  double slope = 0, intercept = 0, squared_residual = 0;
};

Line least_squares(const std::vector<double>& x, const std::vector<double>& y) {
  const double n = static_cast<double>(x.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sx += x[i];
    sy += y[i];
    sxx += x[i] * x[i];
    sxy += x[i] * y[i];
  }
  Line line;
  line.slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  line.intercept = (sy - line.slope * sx) / n;
  for (size_t i = 0; i < x.size(); ++i) line.squared_residual += std::pow(y[i] - line.slope * x[i] - line.intercept, 2);
  return line;
}

// The fit at a given k: ln W = ln(C rho_b sqrt g) + n ln(D - k d).
struct AtK {
  const std::vector<double>& D;
  const std::vector<double>& W;
  double d;
  Line operator()(double k) const {
    std::vector<double> x, y;
    for (size_t i = 0; i < D.size(); ++i) {
      x.push_back(std::log(D[i] - k * d));
      y.push_back(std::log(W[i]));
    }
    return least_squares(x, y);
  }
};

void check(const std::vector<double>& D, const std::vector<double>& W, size_t at_least) {
  if (D.size() != W.size() || D.size() < at_least)
    throw std::invalid_argument("Beverloo fit: needs " + std::to_string(at_least) + " or more (D, W) pairs");
}

}  // namespace

BeverlooFit fit_beverloo(const std::vector<double>& D, const std::vector<double>& W, double rho_b, double g,
                         double d) {
  check(D, W, 3);
  const AtK at{D, W, d};
  // Scan k up to just below the narrowest width (where D - k d vanishes), then refine the best
  // bracket by golden section (the residual is smooth and, near its minimum, unimodal in k).
  const double k_max = *std::min_element(D.begin(), D.end()) / d * (1 - 1e-6);
  const int steps = 400;
  int best = 0;
  for (int s = 1; s < steps; ++s)
    if (at(k_max * s / steps).squared_residual < at(k_max * best / steps).squared_residual) best = s;
  double lo = k_max * std::max(0, best - 1) / steps, hi = k_max * std::min(steps - 1, best + 1) / steps;
  const double ratio = (std::sqrt(5.0) - 1) / 2;
  for (int it = 0; it < 60; ++it) {
    const double a = hi - ratio * (hi - lo), b = lo + ratio * (hi - lo);
    if (at(a).squared_residual < at(b).squared_residual)
      hi = b;
    else
      lo = a;
  }
  BeverlooFit fit;
  fit.k = 0.5 * (lo + hi);
  const Line line = at(fit.k);
  fit.n = line.slope;
  fit.C = std::exp(line.intercept) / (rho_b * std::sqrt(g));
  fit.rms_log_residual = std::sqrt(line.squared_residual / static_cast<double>(D.size()));
  return fit;
}

BeverlooFit fit_beverloo_fixed_exponent(const std::vector<double>& D, const std::vector<double>& W, double rho_b,
                                        double g, double d, double n) {
  check(D, W, 2);
  std::vector<double> root;
  for (double w : W) root.push_back(std::pow(w, 1 / n));
  const Line line = least_squares(D, root);
  BeverlooFit fit;
  fit.n = n;
  fit.k = -line.intercept / (line.slope * d);
  fit.C = std::pow(line.slope, n) / (rho_b * std::sqrt(g));
  double squared = 0;
  for (size_t i = 0; i < D.size(); ++i)
    squared += std::pow(std::log(W[i]) - n * std::log(line.slope * (D[i] - fit.k * d)), 2);
  fit.rms_log_residual = std::sqrt(squared / static_cast<double>(D.size()));
  return fit;
}

}  // namespace kiln
