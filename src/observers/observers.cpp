#include "src/observers/observers.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include "src/dem/dem_system.h"
#include "src/scene/wall_geometry.h"

namespace kiln {

namespace {

// The particles' materials (walls' materials and particles of walls aside).
std::set<int> particle_materials(const Scene& scene) {
  std::set<int> used;
  for (int i = 0; i < scene.n_particles(); ++i)
    if (scene.attached.empty() || scene.attached[i] == Scene::free_particle) used.insert(scene.material[i]);
  return used;
}

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
std::pair<double, double> mean_and_spread(const double* v, int n) {
  double mean = 0, deviations = 0;
  for (int i = 0; i < n; ++i) mean += v[i] / n;
  for (int i = 0; i < n; ++i) deviations += (v[i] - mean) * (v[i] - mean);
  return {mean, std::sqrt(deviations / n)};
}

// Bounces of particle 0 (cases T1, T2): contact durations from the gap to the nearest wall,
// linearly interpolated between steps (O(dt^2)), and apex heights along -g. After a release the
// flight is ballistic, so the apex follows from the first free sample: h = s + u^2 / (2 |g|),
// with s the height and u the upward speed; no sampling error from the step size.
class BounceObserver final : public Observer {
 public:
  explicit BounceObserver(const DemSystem& sys) : sys_(sys) {
    const Vec2 g = sys.scene().gravity;
    g_ = norm(g);
    up_ = g_ > 0 ? (-1 / g_) * g : Vec2{0, 1};
    release_height_ = dot(sys.scene().position[0], up_);
  }
  void sample(double t, const double* y) override {
    const Vec2 c{y[sys_.x_at()], y[sys_.y_at()]};
    const Vec2 v{y[sys_.vx_at()], y[sys_.vy_at()]};
    sys_.wall_geometry(t, y, a_, b_);
    double gap = INFINITY;
    for (size_t s = 0; s < a_.size(); ++s) {
      const Vec2 ab = b_[s] - a_[s];
      const double along = std::clamp(dot(c - a_[s], ab) / dot(ab, ab), 0.0, 1.0);
      gap = std::min(gap, norm(a_[s] + along * ab - c) - sys_.radius(0));
    }
    if (have_last_) {
      if (last_gap_ > 0 && gap <= 0) onset_ = crossing(t, gap);
      if (last_gap_ <= 0 && gap > 0) {
        durations_.push_back(crossing(t, gap) - onset_);
        awaiting_apex_ = true;
      } else if (awaiting_apex_ && gap > 0) {
        const double u = dot(v, up_);
        heights_.push_back(dot(c, up_) + (g_ > 0 ? u * u / (2 * g_) : 0));
        awaiting_apex_ = false;
      }
    }
    last_gap_ = gap;
    last_t_ = t;
    have_last_ = true;
  }
  void report(double, const double*, nlohmann::json& out) override {
    out["release_height"] = release_height_;
    out["bounce_heights"] = heights_;
    out["contact_durations"] = durations_;
  }
  void state(ObserverState& s) override {
    s.field("last_gap", last_gap_);
    s.field("last_t", last_t_);
    s.field("onset", onset_);
    s.field("have_last", have_last_);
    s.field("awaiting_apex", awaiting_apex_);
    s.field("heights", heights_);
    s.field("durations", durations_);
  }

 private:
  double crossing(double t, double gap) const { return last_t_ + (t - last_t_) * last_gap_ / (last_gap_ - gap); }
  const DemSystem& sys_;
  std::vector<Vec2> a_, b_;
  Vec2 up_;
  double g_ = 0, release_height_ = 0;
  bool have_last_ = false, awaiting_apex_ = false;
  double last_gap_ = 0, last_t_ = 0, onset_ = 0;
  std::vector<double> heights_, durations_;
};

// Rolling or sliding of particle 0 along x (case C1, gravity tilted against a flat floor):
// least-squares slope of vx(t) over the second half of the run, and the slip ratio
// 1 + omega r / vx at the end (0 when rolling without slip, 1 when sliding without spin).
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
    out["slip_ratio"] = 1 + w * sys_.radius(0) / vx;
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

class HeapObserver final : public Observer {
 public:
  explicit HeapObserver(const DemSystem& sys) : sys_(sys) {}
  void report(double, const double* y, nlohmann::json& out) override {
    const int n = sys_.particles();
    std::vector<double> x(y + sys_.x_at(), y + sys_.x_at() + n), h(y + sys_.y_at(), y + sys_.y_at() + n), r(n);
    for (int i = 0; i < n; ++i) r[i] = sys_.radius(i);
    const HeapShape shape = measure_heap(x, h, r);
    auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
    out["heap_angle_deg"] = number(shape.angle_deg);
    out["heap_angle_left_deg"] = number(shape.angle_left_deg);
    out["heap_angle_right_deg"] = number(shape.angle_right_deg);
    out["packing_fraction"] = number(shape.packing_fraction);
  }

 private:
  const DemSystem& sys_;
};

// Temperatures at the end (thermal cases): mean, spread (standard deviation), extremes, heat content sum C_i T_i, the means of
// the particles left and right of x = 0 (Lethe L1), and the least-squares line T = A x + B with its
// rms residual (Lethe L2, the slab and chain cases).
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

// Mean temperature in horizontal layers one mean diameter thick, from the bed's bottom (the lowest
// disc's underside) to its top (the highest disc's top), against the relative height
// eta = (layer centre - bottom) / (top - bottom): Nguyen's Figure 7 (N2).
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

// Mixing of a tracer (the particles that started in the left half, or one species) with the rest,
// by Lacey's index M = (S0^2 - S^2) / (S0^2 - SR^2) (Lacey 1954; the index CASES.md asks
// for in C2): S^2 the weighted variance of the tracer's share over square cells (fixed in space)
// holding at least 3 particles, S0^2 = p (1 - p) fully segregated and SR^2 = S0^2 / n the random
// mixture of cells of n particles (the mean occupancy). 0 segregated,
// 1 random. Sampled every output interval with the bed's tilt and the temperature spread (thermal
// scenes); at the end the bed's shape and its dynamic angle of repose.
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
    out["dynamic_angle_of_repose_deg"] = sum / count;
  }
  void state(ObserverState& s) override {
    s.field("next", next_);
    s.field("time", time_);
    s.field("index", index_);
    s.field("spread", spread_);
    s.field("tilt", tilt_);
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

HeapShape measure_heap(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& r) {
  HeapShape shape;
  const size_t n = x.size();
  double rmean = 0, xmin = INFINITY, xmax = -INFINITY, floor = INFINITY;
  for (size_t i = 0; i < n; ++i) {
    rmean += r[i] / n;
    xmin = std::min(xmin, x[i] - r[i]);
    xmax = std::max(xmax, x[i] + r[i]);
    floor = std::min(floor, y[i] - r[i]);
  }
  // Surface profile: the highest disc top in columns one mean diameter wide.
  const double width = 2 * rmean;
  const int bins = std::max(1, static_cast<int>(std::ceil((xmax - xmin) / width)));
  std::vector<double> top(bins, floor);
  for (size_t i = 0; i < n; ++i) {
    const int b = std::min(bins - 1, static_cast<int>((x[i] - xmin) / width));
    top[b] = std::max(top[b], y[i] + r[i]);
  }
  const int peak = static_cast<int>(std::max_element(top.begin(), top.end()) - top.begin());
  const double height = top[peak] - floor;
  // Slopes: columns whose surface lies between 20 % and 80 % of the heap height on each side
  // (away from the rounded summit and the scattered foot).
  LineFit left_slope, right_slope;
  for (int b = 0; b < bins; ++b) {
    const double rel = (top[b] - floor) / height;
    if (rel < 0.2 || rel > 0.8) continue;
    (b < peak ? left_slope : right_slope).add(xmin + (b + 0.5) * width, top[b]);
  }
  // Fewer than three columns on a side give no slope.
  auto angle = [](const LineFit& f) { return f.n >= 3 ? std::atan(std::abs(f.slope())) * 180 / M_PI : NAN; };
  shape.angle_left_deg = angle(left_slope);
  shape.angle_right_deg = angle(right_slope);
  shape.angle_deg = 0.5 * (shape.angle_left_deg + shape.angle_right_deg);

  // Packing fraction: share of a regular grid of sample points covered by discs, in a window
  // centred under the summit, from two diameters above the floor up to half the height, and as
  // wide as the heap is at half its height, halved.
  int left = peak, right = peak;
  while (left > 0 && top[left - 1] - floor > 0.5 * height) --left;
  while (right < bins - 1 && top[right + 1] - floor > 0.5 * height) ++right;
  const double cx = xmin + (peak + 0.5) * width;
  const double half_w = 0.25 * (right - left + 1) * width;
  double rmax = 0;
  for (double ri : r) rmax = std::max(rmax, ri);
  const double y0 = floor + 4 * rmax, y1 = floor + 0.5 * height;
  if (y1 <= y0 || half_w <= 2 * rmax) return shape;
  std::map<std::pair<long, long>, std::vector<size_t>> cells;
  const double cell = 2 * rmax;
  for (size_t i = 0; i < n; ++i) cells[{std::lround(std::floor(x[i] / cell)), std::lround(std::floor(y[i] / cell))}].push_back(i);
  const int samples = 200;
  long covered = 0;
  for (int a = 0; a < samples; ++a)
    for (int b = 0; b < samples; ++b) {
      const double px = cx - half_w + 2 * half_w * (a + 0.5) / samples;
      const double py = y0 + (y1 - y0) * (b + 0.5) / samples;
      const long gx = std::lround(std::floor(px / cell)), gy = std::lround(std::floor(py / cell));
      bool inside = false;
      for (long dx = -1; dx <= 1 && !inside; ++dx)
        for (long dy = -1; dy <= 1 && !inside; ++dy) {
          const auto it = cells.find({gx + dx, gy + dy});
          if (it == cells.end()) continue;
          for (size_t i : it->second)
            if ((px - x[i]) * (px - x[i]) + (py - y[i]) * (py - y[i]) < r[i] * r[i]) inside = true;
        }
      covered += inside;
    }
  shape.packing_fraction = static_cast<double>(covered) / (samples * samples);
  return shape;
}

namespace {

// Every observer a scene may name under `report`, with its factory. Observers of one case live in
// files of their own (observe_*.cpp) and are declared in observers.h.
template <class T>
std::unique_ptr<Observer> make(const DemSystem& system) {
  return std::make_unique<T>(system);
}
std::string needs_heat(const Scene& scene) { return scene.thermal ? "" : "a thermal scene"; }
std::string needs_walls(const Scene& scene) { return scene.walls.empty() ? "walls" : ""; }
std::string needs_species(const Scene& scene) {
  return particle_materials(scene).size() >= 2 ? "" : "particles of two materials (the species)";
}
template <MixingObserver::Tracer tracer>
std::unique_ptr<Observer> make_mixing(const DemSystem& system) {
  return std::make_unique<MixingObserver>(system, tracer);
}
struct Entry {
  const char* name;
  std::unique_ptr<Observer> (*factory)(const DemSystem&);
  std::string (*unmet)(const Scene&);  // what the scene lacks for this observer, or ""
};
const Entry registry[] = {
    {"bounce_heights", make<BounceObserver>, nullptr},
    {"discharge", make_discharge_observer, discharge_observer_needs},
    {"heap", make<HeapObserver>, nullptr},
    {"incline_motion", make<InclineObserver>, nullptr},
    {"mixing", make_mixing<MixingObserver::Tracer::left_half>, nullptr},
    {"species_mixing", make_mixing<MixingObserver::Tracer::first_material>, needs_species},
    {"shear_profile", make_shear_observer, shear_observer_needs},
    {"temperatures", make<TemperatureObserver>, needs_heat},
    {"temperature_profile", make<TemperatureProfileObserver>, needs_heat},
    {"wall_impacts", make_impact_observer, needs_walls},
};

}  // namespace

const std::vector<std::string>& observer_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const Entry& e : registry) v.emplace_back(e.name);
    return v;
  }();
  return names;
}

std::string observer_needs(const std::string& name, const Scene& scene) {
  for (const Entry& e : registry)
    if (name == e.name) return e.unmet ? e.unmet(scene) : "";
  return "";
}

std::unique_ptr<Observer> make_observer(const std::string& name, const DemSystem& system) {
  for (const Entry& e : registry)
    if (name == e.name) return e.factory(system);
  throw std::logic_error("make_observer: unknown observer " + name);  // the scene reader checked the name
}

}  // namespace kiln
