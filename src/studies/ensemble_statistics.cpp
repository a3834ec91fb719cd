#include "src/studies/ensemble_statistics.h"

#include <boost/math/distributions/students_t.hpp>
#include <cmath>

#include "src/base/error.h"
#include "src/studies/study_report.h"

namespace kiln {

namespace {

// The interval, p-value and detectable bias of an estimate with its standard error and degrees
// of freedom.
Bias with_interval(std::string test, int n, double estimate, double se, double dof, double level, double power) {
  Bias b;
  b.test = std::move(test);
  b.n = n;
  b.estimate = estimate;
  b.se = se;
  b.dof = dof;
  if (!(dof > 0) || !std::isfinite(estimate) || !std::isfinite(se)) {
    b.low = b.high = b.p_value = b.detectable = NAN;
    return b;
  }
  const double half = t_quantile(dof, 0.5 + level / 2) * se;
  b.low = estimate - half;
  b.high = estimate + half;
  if (se > 0) {
    const boost::math::students_t t(dof);
    b.p_value = 2 * boost::math::cdf(boost::math::complement(t, std::fabs(estimate) / se));
  } else {
    b.p_value = estimate == 0 ? 1 : 0;
  }
  b.detectable = (t_quantile(dof, 0.5 + level / 2) + t_quantile(dof, power)) * se;
  return b;
}

void check_level(double level, double power) {
  if (!(level > 0 && level < 1)) throw InputError("a confidence level in (0, 1) is needed, got " + message_number(level));
  if (!(power > 0 && power < 1)) throw InputError("a power in (0, 1) is needed, got " + message_number(power));
}

}  // namespace

double t_quantile(double dof, double p) { return boost::math::quantile(boost::math::students_t(dof), p); }

Ensemble ensemble_of(const std::vector<double>& values, double level) {
  Ensemble e;
  e.n = static_cast<int>(values.size());
  if (e.n == 0) {
    e.mean = e.sd = e.se = e.low = e.high = NAN;
    return e;
  }
  for (double v : values) e.mean += v / e.n;
  double squares = 0;  // two passes: a mean far above the spread would cancel in sum x^2 - n mean^2
  for (double v : values) squares += (v - e.mean) * (v - e.mean);
  if (e.n < 2 || !std::isfinite(e.mean)) {
    e.sd = e.se = e.low = e.high = NAN;
    return e;
  }
  e.sd = std::sqrt(squares / (e.n - 1));
  e.se = e.sd / std::sqrt(e.n);
  const double half = t_quantile(e.n - 1, 0.5 + level / 2) * e.se;
  e.low = e.mean - half;
  e.high = e.mean + half;
  return e;
}

Bias paired_bias(const std::vector<double>& point, const std::vector<double>& reference, double level, double power) {
  check_level(level, power);
  if (point.size() != reference.size())
    throw InputError("a paired test needs one reference value per seed: " + std::to_string(point.size()) +
                     " values against " + std::to_string(reference.size()));
  std::vector<double> d(point.size());
  for (size_t k = 0; k < d.size(); ++k) d[k] = point[k] - reference[k];
  const Ensemble e = ensemble_of(d, level);
  return with_interval("paired t", e.n, e.mean, e.se, e.n - 1, level, power);
}

Bias welch_bias(const std::vector<double>& point, const std::vector<double>& reference, double level, double power) {
  check_level(level, power);
  const Ensemble a = ensemble_of(point, level), b = ensemble_of(reference, level);
  const double va = a.se * a.se, vb = b.se * b.se;
  // Welch-Satterthwaite: the degrees of freedom of a sum of two variances estimated apart.
  const double dof = (va + vb) * (va + vb) / (va * va / (a.n - 1) + vb * vb / (b.n - 1));
  return with_interval("Welch t", a.n, a.mean - b.mean, std::sqrt(va + vb), va + vb > 0 ? dof : a.n + b.n - 2, level,
                       power);
}

Bias exact_bias(const std::vector<double>& point, double exact, double level, double power) {
  check_level(level, power);
  const Ensemble e = ensemble_of(point, level);
  return with_interval("one-sample t", e.n, e.mean - exact, e.se, e.n - 1, level, power);
}

BiasVerdict verdict_of(const Bias& bias, double tolerance) {
  if (tolerance > 0 && bias.low > -tolerance && bias.high < tolerance) return BiasVerdict::within_tolerance;
  return bias.detected() ? BiasVerdict::biased : BiasVerdict::undetected;
}

std::string describe(const Bias& bias, double tolerance) {
  if (!std::isfinite(bias.low)) return "no verdict: fewer than two seeds or a failed run";
  switch (verdict_of(bias, tolerance)) {
    case BiasVerdict::within_tolerance:
      return format("within %.3g (bias %.3g in [%.3g, %.3g])", tolerance, bias.estimate, bias.low, bias.high);
    case BiasVerdict::biased: return format("biased by %.3g +- %.2g", bias.estimate, (bias.high - bias.low) / 2);
    case BiasVerdict::undetected:
      return format("no bias detectable at N = %d (smallest detectable %.2g)%s", bias.n, bias.detectable,
                    tolerance > 0 ? "; more seeds may decide against the tolerance" : "");
  }
  return "";
}

}  // namespace kiln
