#include "src/output/colour_scale.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace kiln {

double ColourScale::position(double v) const {
  if (constant || !std::isfinite(v)) return 0.5;
  return std::clamp((v - low) / (high - low), 0.0, 1.0);
}

ColourScale colour_scale(const std::vector<double>& values) {
  std::vector<double> finite;
  for (double v : values)
    if (std::isfinite(v)) finite.push_back(v);
  ColourScale s;
  if (finite.empty()) {
    s.constant = true;
    return s;
  }
  std::sort(finite.begin(), finite.end());
  const double min = finite.front(), max = finite.back();
  if (max - min <= 1e-9 * std::max(std::abs(min), std::abs(max))) {
    s.constant = true;
    s.low = s.high = 0.5 * (min + max);
    return s;
  }
  const auto at = [&](double q) { return finite[static_cast<size_t>(std::floor(q * (finite.size() - 1)))]; };
  s.low = at(0.02);
  s.high = at(0.98);
  if (!(s.high > s.low) || max - min <= 2 * (s.high - s.low)) {
    s.low = min;
    s.high = max;
  }
  s.clipped_low = min < s.low;
  s.clipped_high = max > s.high;
  return s;
}

double round_length(double at_most) {
  const double decade = std::pow(10.0, std::floor(std::log10(at_most)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * decade <= at_most) return m * decade;
  return decade;
}

std::string scale_label(double value, double span) {
  if (std::abs(value) <= 1e-6 * span) return "0";
  const int digits =
      span > 0 ? std::clamp(static_cast<int>(std::ceil(std::log10(std::abs(value) / span))) + 3, 3, 12) : 4;
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return text;
}

}  // namespace kiln
