// The small statistics several observers share.
#pragma once
#include <cmath>
#include <utility>

namespace kiln {

// Least-squares straight line y = slope x + intercept, accumulated point by point.
struct LineFit {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  void add(double x, double y) {
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  double slope() const { return n >= 2 ? (n * sxy - sx * sy) / (n * sxx - sx * sx) : NAN; }
  double intercept() const { return (sy - slope() * sx) / n; }
};

// Mean and standard deviation of n values (two passes: no cancellation when the spread is small).
inline std::pair<double, double> mean_and_spread(const double* v, int n) {
  double mean = 0, deviations = 0;
  for (int i = 0; i < n; ++i) mean += v[i] / n;
  for (int i = 0; i < n; ++i) deviations += (v[i] - mean) * (v[i] - mean);
  return {mean, std::sqrt(deviations / n)};
}

}  // namespace kiln
