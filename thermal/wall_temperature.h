// The temperature of an isothermal wall as a function of time: constant, piecewise constant
// steps (e.g. 0 C until 8 s, then 50 C), or a piecewise linear ramp held at its ends.
#pragma once
#include <vector>

namespace kiln::thermal {

struct WallTemperature {
  enum class Kind { adiabatic, steps, ramp } kind = Kind::adiabatic;
  std::vector<double> times, values;  // sorted times; steps: value from times[k] on

  bool isothermal() const { return kind != Kind::adiabatic; }
  double at(double t) const {
    if (kind == Kind::steps) {
      double v = values.front();
      for (size_t k = 0; k < times.size() && times[k] <= t; ++k) v = values[k];
      return v;
    }
    if (t <= times.front()) return values.front();
    for (size_t k = 1; k < times.size(); ++k)
      if (t <= times[k]) return values[k - 1] + (values[k] - values[k - 1]) * (t - times[k - 1]) / (times[k] - times[k - 1]);
    return values.back();
  }
};

}  // namespace kiln::thermal
