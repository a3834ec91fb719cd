// Rolling or sliding of particle 0 along x (case C1, gravity tilted against a flat floor):
// least-squares slope of vx(t) over the second half of the run, and the slip ratio
// 1 + omega r / vx at the end (0 when rolling without slip, 1 when sliding without spin).
#include "src/dem/dem_system.h"
#include "src/observers/observer.h"
#include "src/observers/statistics.h"

namespace kiln {

namespace {

class InclineObserver final : public Observer {
 public:
  explicit InclineObserver(const DemSystem& sys) : sys_(sys), from_(sys.scene().t_end / 2) {}
  void sample(double t, const double* y) override {
    if (t >= from_) fit_.add(t, y[sys_.vx_at()]);
  }
  void report(double, const double* y, nlohmann::json& out) override {
    const double slope = fit_.slope();
    const double vx = y[sys_.vx_at()];
    const double w = sys_.rotates() ? y[sys_.omega_at()] : 0.0;
    out["incline_acceleration"] = slope;
    out["slip_ratio"] = number_or_null(1 + w * sys_.radius(0) / vx);
  }
  void state(ObserverState& s) override {
    s.field("fit_n", fit_.n);
    s.field("fit_sx", fit_.sx);
    s.field("fit_sy", fit_.sy);
    s.field("fit_sxx", fit_.sxx);
    s.field("fit_sxy", fit_.sxy);
  }

 private:
  const DemSystem& sys_;
  double from_;
  LineFit fit_;
};

}  // namespace

std::unique_ptr<Observer> make_incline_observer(const DemSystem& system) {
  return std::make_unique<InclineObserver>(system);
}

}  // namespace kiln
