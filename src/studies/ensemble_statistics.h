// Statistics of ensembles: runs of one scene that differ only in what the scene declares random
// (its fill's seed, jitter, random velocities). On chaotic flows (heaps, drums, mills, hoppers,
// shear cells) one trajectory has no reference beyond its Lyapunov time, and what a study can
// state about a quantity is a statement about its ensemble mean, with a confidence interval.
//
// Intervals and tests are Student's t (Student 1908; Boost.Math's students_t quantiles): the
// ensemble sizes a study can afford are small (4 to 64), where the normal quantile would make
// intervals too narrow (1.96 against 3.18 at n = 4), and the means of the quantities studied
// (angles, rates, friction coefficients, each an average over many grains and times) are close
// to normal by the central limit theorem.
//
// A bias against a reference ensemble run with the same seeds is tested on the per-seed
// differences (the paired t test): the runs of one seed start from the same fill, so their
// difference varies less than either run, and the test is exact whatever that correlation is.
// Against reference ensembles of other seeds, Welch's test (Welch 1947, unequal variances, the
// Welch-Satterthwaite degrees of freedom); against an exact value, the one-sample t test.
#pragma once
#include <string>
#include <vector>

namespace kiln {

// The mean of n values, their sample standard deviation, the standard error of the mean and its
// two-sided confidence interval at `level` (0.95: 95 %). NaN where n is too small (n < 2 for all
// but the mean); any NaN value makes everything NaN.
struct Ensemble {
  int n = 0;
  double mean = 0, sd = 0, se = 0, low = 0, high = 0;
};
Ensemble ensemble_of(const std::vector<double>& values, double level);

// The bias of a point (an integrator and a step) against a reference: its estimate (point minus
// reference), standard error, confidence interval at `level`, two-sided p-value of "no bias",
// and the smallest bias the test detects with probability `power` at that level
// ((t_{1 - alpha/2} + t_{power}) SE, the usual minimum detectable effect).
struct Bias {
  std::string test;  // "paired t", "Welch t", "one-sample t"
  int n = 0;
  double estimate = 0, se = 0, dof = 0, low = 0, high = 0, p_value = 1, detectable = 0;
  bool detected() const { return low > 0 || high < 0; }
};
// `point` and `reference` hold one value per seed, seed k at index k in both.
Bias paired_bias(const std::vector<double>& point, const std::vector<double>& reference, double level, double power);
Bias welch_bias(const std::vector<double>& point, const std::vector<double>& reference, double level, double power);
Bias exact_bias(const std::vector<double>& point, double exact, double level, double power);

// What a bias says against a tolerance E (none: E <= 0):
//  - "within E": the whole interval inside (-E, E) (two one-sided tests at the same level);
//  - "biased by X +- Y" (Y the interval's half width): the interval excludes 0 and, with E, does
//    not lie inside (-E, E);
//  - "no bias detectable at this N (smallest detectable D)": the interval holds 0 and, with E,
//    reaches beyond it: more seeds would decide.
enum class BiasVerdict { within_tolerance, biased, undetected };
BiasVerdict verdict_of(const Bias& bias, double tolerance);
std::string describe(const Bias& bias, double tolerance);

// The t quantile of `dof` degrees of freedom at probability p (dof may be fractional: Welch).
double t_quantile(double dof, double p);

}  // namespace kiln
