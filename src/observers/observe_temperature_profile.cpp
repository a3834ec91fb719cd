// Mean temperature in horizontal layers one mean diameter thick, from the bed's bottom (the lowest
// disc's underside) to its top (the highest disc's top), against the relative height
// eta = (layer centre - bottom) / (top - bottom): Nguyen's Figure 7 (N2).
#include <algorithm>
#include <cmath>

#include "src/dem/dem_system.h"
#include "src/observers/observer.h"

namespace kiln {

namespace {

class TemperatureProfileObserver final : public Observer {
 public:
  explicit TemperatureProfileObserver(const DemSystem& sys) : sys_(sys) {}
  void report(double, const double* y, nlohmann::json& out) override {
    const int n = sys_.particles();
    const double *temp = y + sys_.temperature_at(), *py = y + sys_.y_at();
    double bottom = INFINITY, top = -INFINITY, mean_radius = 0;
    for (int i = 0; i < n; ++i) {
      bottom = std::min(bottom, py[i] - sys_.radius(i));
      top = std::max(top, py[i] + sys_.radius(i));
      mean_radius += sys_.radius(i) / n;
    }
    const int layers = std::max(1, static_cast<int>(std::lround((top - bottom) / (2 * mean_radius))));
    const double thickness = (top - bottom) / layers;
    std::vector<double> sum(layers, 0.0), count(layers, 0.0);
    for (int i = 0; i < n; ++i) {
      const int k = std::clamp(static_cast<int>((py[i] - bottom) / thickness), 0, layers - 1);
      sum[k] += temp[i];
      count[k] += 1;
    }
    nlohmann::json eta = nlohmann::json::array(), mean = nlohmann::json::array();
    for (int k = 0; k < layers; ++k) {
      if (count[k] == 0) continue;
      eta.push_back((k + 0.5) / layers);
      mean.push_back(sum[k] / count[k]);
    }
    out["temperature_profile"] = {{"eta", eta}, {"temperature", mean}, {"bed_height", top - bottom}};
  }

 private:
  const DemSystem& sys_;
};

}  // namespace

std::unique_ptr<Observer> make_temperature_profile_observer(const DemSystem& system) {
  return std::make_unique<TemperatureProfileObserver>(system);
}

}  // namespace kiln
