// Bounces of particle 0 (cases T1, T2): contact durations from the gap to the nearest wall,
// linearly interpolated between steps (O(dt^2)), and apex heights along -g. After a release the
// flight is ballistic, so the apex follows from the first free sample: h = s + u^2 / (2 |g|),
// with s the height and u the upward speed; no sampling error from the step size.
#include <algorithm>
#include <cmath>

#include "src/dem/dem_system.h"
#include "src/observers/observer.h"

namespace kiln {

namespace {

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

}  // namespace

std::unique_ptr<Observer> make_bounce_observer(const DemSystem& system) { return std::make_unique<BounceObserver>(system); }

}  // namespace kiln
