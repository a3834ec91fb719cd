// Discharge through an orifice (case C3): the mass that has passed down through the floor's plane
// over time, the steady discharge rate, and the bin's bulk density, for Beverloo's law
// W = C rho_b sqrt(g) (D - k d)^(3/2) (src/observers/beverloo_fit.h).
//
// Units follow the scene's mass model: W in kg/s of the discs' masses (spheres, or cylinders of
// the scene's thickness) and rho_b as the mass of the discs per unit area of the plane (kg/m^2),
// so that C comes out dimensionless under either model.
#include <algorithm>
#include <cmath>

#include "src/dem/dem_system.h"
#include "src/observers/observer.h"
#include "src/observers/statistics.h"
#include "src/scene/scene_features.h"

namespace kiln {

namespace {

// The discharge plane is the floor: the lowest wall vertex (a flat-bottomed bin's bottom). A disc
// is discharged each time its centre passes down through that plane; in a cell periodic along y
// (discharged discs fed back in at the top, a constant head) through any image of it, so its
// continuous position counts every pass. Passing back up counts -1: the count is the net flux.
// History every output interval: time, discharged mass and count, and the bulk density.
// The steady window starts once 20 % of the run's final discharged mass has passed (the fill has
// fallen into a bed and the flow has set in). Where discharged discs come back in (a cell periodic
// along y: a constant head) it runs to the end; in a bin that drains it ends at 70 %, before the
// last layers, whose rate falls with the head.
class DischargeObserver final : public Observer {
 public:
  explicit DischargeObserver(const DemSystem& sys) : sys_(sys), interval_(sys.scene().output_interval) {
    const Scene& sc = sys.scene();
    const Orifice o = find_orifice(sc.segments);
    plane_ = o.plane;
    orifice_ = o.width;
    centre_ = o.centre;
    for (int i = 0; i < sc.n_particles(); ++i) {
      level_.push_back(level(sc.position[i].y));
      diameter_ += 2 * sc.radius[i] / sc.n_particles();
    }
  }
  void sample(double t, const double* y) override {
    const double* py = y + sys_.y_at();
    for (int i = 0; i < sys_.particles(); ++i) {
      const long now = level(py[i]);
      if (now == level_[i]) continue;
      mass_ += sys_.mass(i) * static_cast<double>(level_[i] - now);
      count_ += static_cast<double>(level_[i] - now);
      level_[i] = now;
    }
    if (t < next_) return;
    next_ = (std::floor(t / interval_ + 1e-9) + 1) * interval_;
    record(t, y);
  }
  void report(double t, const double* y, nlohmann::json& out) override {
    if (time_.empty() || time_.back() < t) record(t, y);
    // The rate: the least-squares slope of the discharged mass over the steady window; its
    // standard error from the spread of the mean rates of 8 consecutive blocks of the window.
    const double total = mass_history_.back();
    const double end = sys_.cell().y ? INFINITY : 0.7 * total;
    size_t from = 0, to = 0;
    while (from < time_.size() && mass_history_[from] < 0.2 * total) ++from;
    for (to = from; to < time_.size() && mass_history_[to] <= end;) ++to;
    // Fewer than two samples a block leave every figure of the window NaN (null).
    const size_t blocks = 8, samples = to - from;
    double rate = NAN, error = NAN, count_rate = NAN, density = NAN, packing = NAN;
    if (samples >= 2 * blocks) {
      rate = slope(mass_history_, from, to);
      count_rate = slope(count_history_, from, to);
      density = packing = 0;
      for (size_t k = from; k < to; ++k) {
        density += density_[k] / static_cast<double>(samples);
        packing += packing_[k] / static_cast<double>(samples);
      }
      double sum = 0, squares = 0;
      for (size_t b = 0; b < blocks; ++b) {
        const size_t first = from + b * (samples - 1) / blocks, last = from + (b + 1) * (samples - 1) / blocks;
        const double block_rate = (mass_history_[last] - mass_history_[first]) / (time_[last] - time_[first]);
        sum += block_rate;
        squares += block_rate * block_rate;
      }
      error = std::sqrt(std::max(0.0, squares / blocks - std::pow(sum / blocks, 2)) / (blocks - 1));
    }
    out["discharge_rate"] = number_or_null(rate);
    out["discharge_rate_error"] = number_or_null(error);
    out["discharge_rate_count"] = number_or_null(count_rate);
    out["discharge_window"] =
        samples >= 2 * blocks ? nlohmann::json{time_[from], time_[to - 1]} : nlohmann::json(nullptr);
    out["bulk_density"] = number_or_null(density);
    out["bed_packing_fraction"] = number_or_null(packing);
    out["mean_diameter"] = diameter_;
    out["orifice_width"] = number_or_null(orifice_);
    out["discharge_plane"] = number_or_null(plane_);
    out["discharged_mass"] = mass_;
    out["discharged_count"] = count_;
    out["discharge_history"] = {{"time", time_},
                                {"discharged_mass", mass_history_},
                                {"discharged_count", count_history_},
                                {"bulk_density", density_}};
  }
  void state(ObserverState& s) override {
    s.field("level", level_, {level_.size()});  // one per particle, as constructed
    s.field("mass", mass_);
    s.field("count", count_);
    s.field("next", next_);
    // One sample of each series at each time (read back: the lengths the report walks together).
    s.field("time", time_);
    s.field("mass_history", mass_history_, {time_.size()});
    s.field("count_history", count_history_, {time_.size()});
    s.field("density", density_, {time_.size()});
    s.field("packing", packing_, {time_.size()});
  }

 private:
  // Least-squares slope of v against time over the samples [from, to).
  double slope(const std::vector<double>& v, size_t from, size_t to) const {
    LineFit fit;
    for (size_t k = from; k < to; ++k) fit.add(time_[k], v[k]);
    return fit.slope();
  }
  // Which side of the plane a centre at height y lies on: 0 above, -1 below; periodic along y,
  // which image of the plane lies just below it (its continuous position counts the passes).
  long level(double y) const {
    const PeriodicCell& c = sys_.cell();
    if (c.y) return std::lround(std::floor((y - plane_) / c.length_y()));
    return y < plane_ ? -1 : 0;
  }
  void record(double t, const double* y) {
    time_.push_back(t);
    mass_history_.push_back(mass_);
    count_history_.push_back(count_);
    bed_density(y);
  }
  // Bulk density of the material at rest: the mass (and disc area) of the discs whose centres lie
  // between 2 and 8 mean diameters above the plane, more than two mean diameters from the bed's
  // sides (the walls order the discs next to them) and more than D from the orifice's centre
  // (the flowing, dilated region above it), per unit area: the bin's bottom corners, where the
  // flow leaves the discs at rest. The bed's sides: the extremes of the discs above the plane.
  void bed_density(const double* y) {
    const PeriodicCell& c = sys_.cell();
    std::vector<Vec2> place;
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < sys_.particles(); ++i) {
      place.push_back(c.wrap({y[sys_.x_at() + i], y[sys_.y_at() + i]}));
      if (place[i].y < plane_) continue;
      lo = std::min(lo, place[i].x - sys_.radius(i));
      hi = std::max(hi, place[i].x + sys_.radius(i));
    }
    const double x0 = lo + 2 * diameter_, x1 = hi - 2 * diameter_;
    const double y0 = plane_ + 2 * diameter_, y1 = plane_ + 8 * diameter_;
    const double reach = std::isnan(orifice_) ? 0 : orifice_;  // no orifice: nothing left out
    auto inside = [&](Vec2 p) {
      return p.x >= x0 && p.x < x1 && p.y >= y0 && p.y < y1 && std::abs(p.x - centre_) >= reach;
    };
    double mass = 0, area = 0;
    for (int i = 0; i < sys_.particles(); ++i)
      if (inside(place[i])) {
        mass += sys_.mass(i);
        area += M_PI * sys_.radius(i) * sys_.radius(i);
      }
    const double left_out = std::max(0.0, std::min(x1, centre_ + reach) - std::max(x0, centre_ - reach));
    const double window = std::max(0.0, x1 - x0 - left_out) * (y1 - y0);
    density_.push_back(window > 0 ? mass / window : NAN);
    packing_.push_back(window > 0 ? area / window : NAN);
  }

  const DemSystem& sys_;
  double interval_, next_ = 0;
  double plane_ = INFINITY, orifice_ = NAN, centre_ = 0, diameter_ = 0;
  std::vector<long> level_;
  double mass_ = 0, count_ = 0;
  std::vector<double> time_, mass_history_, count_history_, density_, packing_;
};

}  // namespace

std::unique_ptr<Observer> make_discharge_observer(const DemSystem& system) {
  return std::make_unique<DischargeObserver>(system);
}

}  // namespace kiln
