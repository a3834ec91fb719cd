// Restitution <-> dashpot coefficient for the normal models (see normal_force.h).
#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <tuple>

#include "contact/normal_force.h"

namespace kiln::contact {

namespace {

// Dimensionless relative acceleration u'' for overlap u and rate w = u' under the spring of
// `Spring` with unit k and c = beta, the contact law continued smoothly to u < 0 (odd extension)
// so that the step that crosses separation is integrated on a smooth right-hand side; the
// crossing itself is then interpolated.
template <class Spring>
double accel(double u, double w, double beta, bool tension) {
  const double m = std::abs(u);
  const double spring = std::copysign(Spring::spring(1.0, m), u);
  const double dash = beta * Spring::dashpot_scale(m) * w;
  const double f = spring + dash;
  return (!tension && f < 0) ? 0.0 : -f;
}

// A contact whose energy has fallen below this can only end with e < 1e-4 (it starts at 1/2 and
// the dashpot only takes energy out): a hundred times below the least restitution a scene may give,
// so it is called inelastic at once instead of followed while an overdamped dashpot creeps apart.
constexpr double inelastic_energy = 0.5e-8;

template <class Spring>
double restitution_of(double beta, bool tension) {
  // Classical RK4 on (u, w) from first touch at unit speed until the overlap closes again.
  // The contact lasts about pi (linear) or 3.2 (Hertz) in these units. The separation instant
  // inside the last step is found on the cubic Hermite interpolant of u (Newton), and the speed
  // there from the Hermite interpolant of w, keeping the fourth-order accuracy of the steps.
  const double h = 1e-4;
  double u = 0, w = 1, a = accel<Spring>(u, w, beta, tension);
  for (int step = 0; step < 10000000; ++step) {
    const double k1u = w, k1w = a;
    const double k2u = w + 0.5 * h * k1w, k2w = accel<Spring>(u + 0.5 * h * k1u, k2u, beta, tension);
    const double k3u = w + 0.5 * h * k2w, k3w = accel<Spring>(u + 0.5 * h * k2u, k3u, beta, tension);
    const double k4u = w + h * k3w, k4w = accel<Spring>(u + h * k3u, k4u, beta, tension);
    const double un = u + h / 6 * (k1u + 2 * k2u + 2 * k3u + k4u);
    const double wn = w + h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w);
    if (un <= 0 && step > 0) {
      const double an = accel<Spring>(0, wn, beta, tension);
      auto hermite = [](double s, double p0, double m0, double p1, double m1) {
        const double s2 = s * s, s3 = s2 * s;
        return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * m1;
      };
      auto hermite_slope = [](double s, double p0, double m0, double p1, double m1) {
        const double s2 = s * s;
        return (6 * s2 - 6 * s) * p0 + (3 * s2 - 4 * s + 1) * m0 + (-6 * s2 + 6 * s) * p1 + (3 * s2 - 2 * s) * m1;
      };
      double s = u / (u - un);
      for (int it = 0; it < 20; ++it) {
        const double f = hermite(s, u, h * w, un, h * wn);
        const double df = hermite_slope(s, u, h * w, un, h * wn);
        if (df == 0) break;
        s = std::clamp(s - f / df, 0.0, 1.0);
      }
      return -hermite(s, w, h * a, wn, h * an);
    }
    if (wn >= 0 && un > 0 && w < 0) return 0;  // came to rest in contact: fully inelastic
    if (un > 0 && 0.5 * wn * wn + Spring::energy(1.0, un) < inelastic_energy) return 0;
    u = un;
    w = wn;
    a = accel<Spring>(u, w, beta, tension);
  }
  return 0;
}

// Restitution falls monotonically with beta: bracket by doubling, then bisect. Scenes give
// e >= 0.01 (src/scene/scene_values.cpp), which every law reaches below beta = 16; the bracket stops at
// beta = 1024 (e about 1e-4 without tension, 0 with it), so that no e, however small, makes it grow
// without end, and the bisection stops after 60 halvings.
double bisect_damping(double e, NormalModel model, bool tension) {
  double lo = 0, hi = 1;
  for (int doubling = 0; doubling < 10 && restitution_for_damping(hi, model, tension) > e; ++doubling) {
    lo = hi;
    hi *= 2;
  }
  for (int it = 0; it < 60 && hi - lo > 1e-10 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (restitution_for_damping(mid, model, tension) > e ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

double restitution_for_damping(double beta, NormalModel model, bool tension) {
  return with_normal_model(model, [&](auto spring) { return restitution_of<decltype(spring)>(beta, tension); });
}

double restitution_damping(double e, NormalModel model, bool tension) {
  if (e >= 1) return 0;
  if (const auto beta = with_normal_model(model, [&](auto m) { return m.closed_form_damping(e, tension); })) return *beta;
  // A bisection costs up to a fifth of a second, and every pair law of every system built (each run
  // of a study, each wall in the stability estimate) asks again: the answers are kept.
  static std::mutex mutex;
  static std::map<std::tuple<double, NormalModel, bool>, double> known;
  const auto key = std::make_tuple(e, model, tension);
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (const auto it = known.find(key); it != known.end()) return it->second;
  }
  const double beta = bisect_damping(e, model, tension);
  const std::lock_guard<std::mutex> lock(mutex);
  if (known.size() >= 4096) known.clear();  // a process that meets ever new restitutions keeps the recent ones
  known[key] = beta;
  return beta;
}

}  // namespace kiln::contact
