// Temperatures at the end (thermal cases): mean, spread (standard deviation), extremes, heat content sum C_i T_i, the means of
// the particles left and right of x = 0 (Lethe L1), and the least-squares line T = A x + B with its
// rms residual (Lethe L2, the slab and chain cases).
#include <algorithm>
#include <cmath>

#include "src/dem/dem_system.h"
#include "src/observers/observer.h"
#include "src/observers/statistics.h"

namespace kiln {

namespace {

class TemperatureObserver final : public Observer {
 public:
  explicit TemperatureObserver(const DemSystem& sys) : sys_(sys) {}
  void report(double, const double* y, nlohmann::json& out) override {
    const int n = sys_.particles();
    const double* temp = y + sys_.temperature_at();
    const double* px = y + sys_.x_at();
    const auto [mean, spread] = mean_and_spread(temp, n);
    double heat = 0, left = 0, right = 0, nl = 0, nr = 0;
    LineFit fit;
    for (int i = 0; i < n; ++i) {
      heat += sys_.heat_capacity(i) * temp[i];
      (px[i] < 0 ? left : right) += temp[i];
      (px[i] < 0 ? nl : nr) += 1;
      fit.add(px[i], temp[i]);
    }
    const double slope = fit.slope(), intercept = fit.intercept();
    double residual = 0;
    for (int i = 0; i < n; ++i) residual += std::pow(temp[i] - (slope * px[i] + intercept), 2) / n;
    out["temperatures"] = std::vector<double>(temp, temp + n);
    out["temperature_mean"] = mean;
    out["temperature_std"] = spread;
    out["temperature_min"] = *std::min_element(temp, temp + n);
    out["temperature_max"] = *std::max_element(temp, temp + n);
    out["heat_content"] = heat;
    out["temperature_mean_left"] = nl > 0 ? nlohmann::json(left / nl) : nlohmann::json(nullptr);
    out["temperature_mean_right"] = nr > 0 ? nlohmann::json(right / nr) : nlohmann::json(nullptr);
    out["temperature_fit"] = {{"slope", slope}, {"intercept", intercept}, {"rms_residual", std::sqrt(residual)}};
  }

 private:
  const DemSystem& sys_;
};

}  // namespace

std::unique_ptr<Observer> make_temperature_observer(const DemSystem& system) {
  return std::make_unique<TemperatureObserver>(system);
}

}  // namespace kiln
