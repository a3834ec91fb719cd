#include "src/stability_guard.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "src/error.h"

namespace kiln {

StabilityGuard::StabilityGuard(const Scene& scene, const DemSystem& sys, const EnergyLedger& initial)
    : scene_(scene), sys_(sys), initial_(initial), estimate_(estimate_stability(scene)) {
  // Without heat sources conduction obeys a maximum principle: no temperature leaves the range
  // of the initial and wall temperatures. A violation beyond 1 % of the range is instability.
  if (scene.thermal && scene.heat_from_dissipation == HeatFromDissipation::none) {
    low_ = *std::min_element(scene.temperature.begin(), scene.temperature.end());
    high_ = *std::max_element(scene.temperature.begin(), scene.temperature.end());
    for (const Wall& w : scene.walls)
      for (double v : w.temperature.values) {
        low_ = std::min(low_, v);
        high_ = std::max(high_, v);
      }
    const double margin = 0.01 * (high_ - low_) + 1e-9;
    low_ -= margin;
    high_ += margin;
  }
}

void StabilityGuard::every_step(double t) const {
  if (sys_.max_overlap_fraction() > scene_.max_overlap_fraction) {
    std::ostringstream s;
    s << "overlap reached " << sys_.max_overlap_fraction() << " of a radius (limit " << scene_.max_overlap_fraction
      << ", checks.max_overlap_fraction)";
    fail(t, s.str());
  }
}

void StabilityGuard::finite(double t, const double* y, int size) const {
  for (int k = 0; k < size; ++k)
    if (!std::isfinite(y[k])) fail(t, "the state holds NaN or infinity (component " + std::to_string(k) + ")");
  if (!sys_.thermal() || !(high_ > low_)) return;
  for (int i = 0; i < sys_.particles(); ++i) {
    const double temp = y[sys_.temperature_at() + i];
    if (temp < low_ || temp > high_) {
      std::ostringstream s;
      s << "temperature of particle " << i << " is " << temp << ", outside the range of the initial and wall "
        << "temperatures [" << low_ << ", " << high_ << "] (maximum principle of conduction)";
      fail(t, s.str());
    }
  }
}

void StabilityGuard::energy(double t, const EnergyLedger& now) const {
  const double throughput = std::abs(initial_.kinetic) + std::abs(now.kinetic) + std::abs(initial_.elastic) +
                            std::abs(now.elastic) + std::abs(now.potential - initial_.potential) +
                            std::abs(now.dissipated_damping) + std::abs(now.dissipated_friction) +
                            std::abs(now.work_by_walls) + std::abs(now.thermal - initial_.thermal) +
                            std::abs(now.heat_from_walls);
  const double error = balance_error(initial_, now);
  if (throughput > 0 && error > 0.25 * throughput) {
    std::ostringstream s;
    s << "energy blow-up: the balance error " << error << " J exceeds a quarter of the energy exchanged ("
      << throughput << " J)";
    fail(t, s.str());
  }
}

nlohmann::json StabilityGuard::figures() const { return nlohmann::json::object(); }

void StabilityGuard::fail(double t, const std::string& what) const {
  std::ostringstream s;
  s << "unstable run at t = " << t << " s: " << what << ". dt = " << dt_ << " s; ";
  if (heat_only_)
    s << "explicit conduction is stable below dt = " << estimate_.thermal_dt_limit << " s";
  else
    s << "the stability estimate recommends dt <= " << estimate_.recommended_dt << " s (contact duration "
      << estimate_.contact_duration << " s, " << estimate_.shortest_pair << "; limit " << estimate_.dt_limit << " s"
      << (std::isfinite(estimate_.thermal_dt_limit)
              ? "; conduction limit " + std::to_string(estimate_.thermal_dt_limit) + " s)"
              : std::string(")"));
  throw InstabilityError(s.str());
}

}  // namespace kiln
