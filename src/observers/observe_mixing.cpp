// Mixing of a tracer (the particles that started in the left half, or one species) with the rest,
// by Lacey's index M = (S0^2 - S^2) / (S0^2 - SR^2) (Lacey 1954; the index CASES.md asks
// for in C2): S^2 the weighted variance of the tracer's share over square cells (fixed in space)
// holding at least 3 particles, S0^2 = p (1 - p) fully segregated and SR^2 = S0^2 / n the random
// mixture of cells of n particles (the mean occupancy). 0 segregated,
// 1 random. Sampled every output interval with the bed's tilt and the temperature spread (thermal
// scenes); at the end the bed's shape and its dynamic angle of repose.
#include <algorithm>
#include <cmath>
#include <map>

#include "src/dem/dem_system.h"
#include "src/observers/observer.h"
#include "src/observers/statistics.h"
#include "src/scene/scene_features.h"

namespace kiln {

namespace {

class MixingObserver final : public Observer {
 public:
  // The tracer: the particles that start left of the mean x (a hot and a cold half, T6, T7), or
  // those of the first species (of the materials particles are made of, the one listed first
  // under `materials`; C2). Particles of walls take no part.
  enum class Tracer { left_half, first_material };
  MixingObserver(const DemSystem& sys, Tracer tracer) : sys_(sys), interval_(sys.scene().output_interval) {
    const Scene& sc = sys.scene();
    double mean_x = 0, mean_r = 0, free = 0;
    for (int i = 0; i < sc.n_particles(); ++i)
      if (!sys.attached(i)) {
        mean_x += sc.position[i].x;
        mean_r += sc.radius[i];
        free += 1;
      }
    mean_x /= free;
    mean_r /= free;
    double largest = 0;
    const int species = *particle_materials(sc).begin();
    for (int i = 0; i < sc.n_particles(); ++i) {
      const bool halves = tracer == Tracer::left_half;
      tracer_.push_back(halves ? sc.position[i].x < mean_x : sc.material[i] == species);
      weight_.push_back(halves ? 1.0 : M_PI * sc.radius[i] * sc.radius[i]);
      if (!sys.attached(i)) largest = std::max(largest, sc.radius[i]);
    }
    // Halves of similar grains: cells three mean diameters wide, shares by count. Species of
    // different sizes: shares by area (a ball is not worth a grain), in cells two of the largest
    // diameters wide, so that a cell of balls holds several.
    cell_ = tracer == Tracer::left_half ? 6 * mean_r : 4 * largest;
  }
  void sample(double t, const double* y) override {
    if (t < next_) return;
    next_ = (std::floor(t / interval_ + 1e-9) + 1) * interval_;
    record(t, y);
  }
  void report(double t, const double* y, nlohmann::json& out) override {
    if (time_.empty() || time_.back() < t) record(t, y);
    out["mixing_index"] = index_.back();
    out["mixing_history"] = {{"time", time_}, {"lacey_index", index_}, {"bed_tilt_deg", tilt_}, {"lacey_cell", cell_}};
    if (sys_.thermal()) out["mixing_history"]["temperature_std"] = spread_;
    const BedShape shape = bed_shape(y);
    out["bed_centre"] = {shape.centre.x, shape.centre.y};
    out["bed_tilt_deg"] = shape.tilt_deg;
    // The dynamic angle of repose: the mean tilt over the second half of the run, once the bed
    // rolls steadily (the first half lets it fall in and climb to its angle).
    double sum = 0, count = 0;
    for (size_t k = 0; k < time_.size(); ++k)
      if (time_[k] >= 0.5 * t) {
        sum += tilt_[k];
        count += 1;
      }
    out["dynamic_angle_of_repose_deg"] = number_or_null(sum / count);
  }
  void state(ObserverState& s) override {
    s.field("next", next_);
    // One sample of each series at each time (read back: the lengths the report walks together).
    s.field("time", time_);
    s.field("index", index_, {time_.size()});
    s.field("spread", spread_, {sys_.thermal() ? time_.size() : 0});
    s.field("tilt", tilt_, {time_.size()});
  }

 private:
  void record(double t, const double* y) {
    time_.push_back(t);
    index_.push_back(lacey(y));
    tilt_.push_back(bed_shape(y).tilt_deg);
    if (sys_.thermal()) spread_.push_back(mean_and_spread(y + sys_.temperature_at(), sys_.particles()).second);
  }
  // The bed's centre of mass and the tilt of its long axis (the principal axis of the
  // mass-weighted positions), positive when it rises to the right: for a bed filling less than
  // half the drum, the long axis lies along the free surface.
  struct BedShape {
    Vec2 centre;
    double tilt_deg = 0;
  };
  BedShape bed_shape(const double* y) const {
    const int n = sys_.particles();
    const double *px = y + sys_.x_at(), *py = y + sys_.y_at();
    double m = 0, cx = 0, cy = 0;
    for (int i = 0; i < n; ++i) {
      m += sys_.mass(i);
      cx += sys_.mass(i) * px[i];
      cy += sys_.mass(i) * py[i];
    }
    cx /= m;
    cy /= m;
    double sxx = 0, syy = 0, sxy = 0;
    for (int i = 0; i < n; ++i) {
      sxx += sys_.mass(i) * (px[i] - cx) * (px[i] - cx);
      syy += sys_.mass(i) * (py[i] - cy) * (py[i] - cy);
      sxy += sys_.mass(i) * (px[i] - cx) * (py[i] - cy);
    }
    return {{cx, cy}, 0.5 * std::atan2(2 * sxy, sxx - syy) * 180 / M_PI};
  }
  double lacey(const double* y) const {
    const int n = sys_.particles();
    const double *px = y + sys_.x_at(), *py = y + sys_.y_at();
    struct Cell {
      double tracer = 0, all = 0;  // weights
      int count = 0;
    };
    std::map<std::pair<long, long>, Cell> cells;
    for (int i = 0; i < n; ++i) {
      if (sys_.attached(i)) continue;
      Cell& c = cells[{std::lround(std::floor(px[i] / cell_)), std::lround(std::floor(py[i] / cell_))}];
      if (tracer_[i]) c.tracer += weight_[i];
      c.all += weight_[i];
      c.count += 1;
    }
    double total = 0, tracer = 0, count = 0, cells_used = 0;
    for (const auto& [key, c] : cells)
      if (c.count >= 3) {
        total += c.all;
        tracer += c.tracer;
        count += c.count;
        cells_used += 1;
      }
    if (cells_used < 2) return NAN;
    const double p = tracer / total, s0 = p * (1 - p), sr = s0 / (count / cells_used);
    double s2 = 0;
    for (const auto& [key, c] : cells)
      if (c.count >= 3) s2 += c.all * std::pow(c.tracer / c.all - p, 2) / total;
    return (s0 - s2) / (s0 - sr);
  }
  const DemSystem& sys_;
  double interval_, cell_ = 0, next_ = 0;
  std::vector<bool> tracer_;
  std::vector<double> weight_;  // of each particle in its cell's share: 1 (count), or its area
  std::vector<double> time_, index_, spread_, tilt_;
};

}  // namespace

std::unique_ptr<Observer> make_mixing_observer(const DemSystem& system) {
  return std::make_unique<MixingObserver>(system, MixingObserver::Tracer::left_half);
}

std::unique_ptr<Observer> make_species_mixing_observer(const DemSystem& system) {
  return std::make_unique<MixingObserver>(system, MixingObserver::Tracer::first_material);
}

}  // namespace kiln
