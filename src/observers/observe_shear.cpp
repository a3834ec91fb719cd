// Plane shear (case N3, Nguyen et al. 2009, section 4.3): a layer between a fixed rough wall and a
// load-controlled rough wall driven at V. Over the second half of the run (the first half lets the
// layer compact under the load and the flow become steady) it accumulates, in layers across the
// gap:
//  - the mean velocity along the drive, against the relative height eta = (y - bottom) / (top -
//    bottom), bottom the lowest disc's underside and top the driven wall, both along the load;
//  - the heat the particles gain, booked to the layer each particle is in at each step (with
//    conduction off, all of it is friction heat: Nguyen's Figure 13, heat against depth);
// and from the driven wall's load, the shear and normal stress (force per unit cell length), the
// effective friction coefficient tau / sigma, the shear rate V / H and the inertial number
// I = gamma_dot d sqrt(rho / P) (GDR MiDi 2004; in 2D rho is the discs' mass per disc area, P the
// normal stress per length).
// Every sample is weighted by its step's length, so adaptive steps average correctly.
#include <algorithm>
#include <cmath>

#include "src/dem/dem_system.h"
#include "src/observers/observer.h"
#include "src/scene/scene_features.h"

namespace kiln {

namespace {

class ShearObserver final : public Observer {
 public:
  explicit ShearObserver(const DemSystem& sys)
      : sys_(sys), wall_(driven_wall(sys.scene())), from_(sys.scene().t_end / 2) {
    const WallMotion& m = sys.scene().walls[wall_].motion;
    up_ = (-1 / norm(m.load)) * m.load;
    drive_ = norm(m.velocity) > 0 ? (1 / norm(m.velocity)) * m.velocity : Vec2{up_.y, -up_.x};
    speed_ = dot(m.velocity, drive_);
    const Scene& sc = sys.scene();
    double mass = 0, area = 0, diameter = 0;
    int free = 0;
    for (int i = 0; i < sc.n_particles(); ++i) {
      if (sys.attached(i)) continue;
      mass += sys.mass(i);
      area += M_PI * sc.radius[i] * sc.radius[i];
      diameter += 2 * sc.radius[i];
      ++free;
    }
    density_ = mass / area;
    diameter_ = diameter / free;
    // Stresses per unit length of the cell: the period, else the driven wall's extent along the drive.
    if (sc.periodic.x) {
      length_ = sc.periodic.x1 - sc.periodic.x0;
    } else {
      double lo = INFINITY, hi = -INFINITY;
      for (const Segment& s : sc.segments)
        if (s.wall == wall_)
          for (Vec2 p : {s.a, s.b}) {
            lo = std::min(lo, dot(p, drive_));
            hi = std::max(hi, dot(p, drive_));
          }
      length_ = hi - lo;
    }
  }

  void sample(double t, const double* y) override {
    const double h = t - last_t_;
    last_t_ = t;
    if (t <= from_) {
      remember_heat(y);
      return;
    }
    // The sums belong to the window [from_, t_end]: a run resumed with another t_end has another
    // window, so what a checkpoint carries from the old one starts over (the window then opens
    // where the resumed run starts, if that is later than its half).
    if (summed_from_ != from_) {
      layers_ = 0;
      shear_ = normal_ = gap_ = span_ = 0;
      summed_from_ = from_;
      opened_ = t - h;
    }
    const int n = sys_.particles();
    const double *px = y + sys_.x_at(), *py = y + sys_.y_at();
    const double *vx = y + sys_.vx_at(), *vy = y + sys_.vy_at();
    double bottom = INFINITY;
    for (int i = 0; i < n; ++i) bottom = std::min(bottom, px[i] * up_.x + py[i] * up_.y - sys_.radius(i));
    sys_.wall_geometry(t, y, a_, b_);
    double top = -INFINITY;
    for (size_t s = 0; s < a_.size(); ++s)
      if (sys_.scene().segments[s].wall == wall_) top = std::max(top, std::max(dot(a_[s], up_), dot(b_[s], up_)));
    const double gap = top - bottom;
    if (layers_ == 0) {
      layers_ = std::max(3, static_cast<int>(std::lround(gap / diameter_)));
      speed_sum_.assign(layers_, 0.0);
      weight_.assign(layers_, 0.0);
      heat_.assign(layers_, 0.0);
    }
    auto layer = [&](int i) {
      const double eta = (px[i] * up_.x + py[i] * up_.y - bottom) / gap;
      return std::clamp(static_cast<int>(eta * layers_), 0, layers_ - 1);
    };
    for (int i = 0; i < n; ++i) {
      if (sys_.attached(i)) continue;
      const int k = layer(i);
      speed_sum_[k] += h * (vx[i] * drive_.x + vy[i] * drive_.y);
      weight_[k] += h;
    }
    if (sys_.thermal()) {
      const double* temp = y + sys_.temperature_at();
      for (int i = 0; i < n; ++i) heat_[layer(i)] += sys_.heat_capacity(i) * (temp[i] - last_temp_[i]);
      remember_heat(y);
    }
    const Vec2 f = sys_.wall_loads()[wall_].force;
    shear_ += -h * dot(f, drive_);
    normal_ += h * dot(f, up_);
    gap_ += h * gap;
    span_ += h;
  }

  void report(double, const double*, nlohmann::json& out) override {
    if (span_ <= 0) {  // the window has not opened: nothing measured
      for (const char* key : {"shear_profile", "shear_stress", "normal_stress", "effective_friction", "shear_rate",
                              "inertial_number"})
        out[key] = nullptr;
      return;
    }
    nlohmann::json eta = nlohmann::json::array(), v = nlohmann::json::array(), vr = nlohmann::json::array();
    for (int k = 0; k < layers_; ++k) {
      eta.push_back((k + 0.5) / layers_);
      const double mean = weight_[k] > 0 ? speed_sum_[k] / weight_[k] : NAN;
      v.push_back(std::isfinite(mean) ? nlohmann::json(mean) : nlohmann::json(nullptr));
      vr.push_back(std::isfinite(mean) ? nlohmann::json(mean / speed_) : nlohmann::json(nullptr));
    }
    const double shear = shear_ / span_, normal = normal_ / span_, gap = gap_ / span_;
    nlohmann::json& p = out["shear_profile"];
    p = {{"window", {opened_, last_t_}}, {"eta", eta}, {"velocity", v}, {"velocity_over_wall", vr},
         {"wall_speed", speed_}, {"gap", gap}};
    if (sys_.thermal()) {
      double total = 0;
      for (double q : heat_) total += q;
      std::vector<double> power(layers_), share(layers_);
      for (int k = 0; k < layers_; ++k) {
        power[k] = heat_[k] / span_;
        share[k] = total != 0 ? heat_[k] / total : 0.0;
      }
      p["heat_power"] = power;
      p["heat_share"] = share;
      p["heat_total"] = total;
    }
    const double per_length = 1 / length_;
    out["shear_stress"] = shear * per_length;
    out["normal_stress"] = normal * per_length;
    out["effective_friction"] = number_or_null(shear / normal);
    const double rate = speed_ / gap;
    out["shear_rate"] = rate;
    out["inertial_number"] = number_or_null(rate * diameter_ * std::sqrt(density_ / (normal * per_length)));
  }

  void state(ObserverState& s) override {
    s.field("last_t", last_t_);
    s.field("summed_from", summed_from_);
    s.field("opened", opened_);
    s.field("layers", layers_);
    s.field("shear", shear_);
    s.field("normal", normal_);
    s.field("gap", gap_);
    s.field("span", span_);
    // Per layer (none before the cell opened), per particle (a thermal run's, once sampled).
    const size_t layers = layers_ >= 0 ? static_cast<size_t>(layers_) : SIZE_MAX;
    s.field("speed_sum", speed_sum_, {layers});
    s.field("weight", weight_, {layers});
    s.field("heat", heat_, {layers});
    s.field("last_temp", last_temp_, {size_t{0}, static_cast<size_t>(sys_.particles())});
  }

 private:
  void remember_heat(const double* y) {
    if (!sys_.thermal()) return;
    const double* temp = y + sys_.temperature_at();
    last_temp_.assign(temp, temp + sys_.particles());
  }

  const DemSystem& sys_;
  int wall_;
  double from_;
  Vec2 up_, drive_;
  double speed_ = 0, density_ = 0, diameter_ = 0, length_ = 0;
  std::vector<Vec2> a_, b_;
  double last_t_ = 0;
  double summed_from_ = NAN, opened_ = 0;  // the window the sums are for, and when they began
  int layers_ = 0;
  std::vector<double> speed_sum_, weight_, heat_, last_temp_;
  double shear_ = 0, normal_ = 0, gap_ = 0, span_ = 0;
};

}  // namespace

std::unique_ptr<Observer> make_shear_observer(const DemSystem& system) { return std::make_unique<ShearObserver>(system); }

}  // namespace kiln
