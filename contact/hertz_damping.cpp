// Restitution <-> dashpot coefficient for the normal laws (see normal_force.h).
#include <cmath>

#include "contact/normal_force.h"

namespace kiln::contact {

namespace {

// Dimensionless relative acceleration u'' for overlap u and rate w = u'.
double accel(double u, double w, double beta, bool hertz, bool tension) {
  if (u <= 0) return 0;
  const double spring = hertz ? u * std::sqrt(u) : u;
  const double dash = beta * (hertz ? std::sqrt(std::sqrt(u)) : 1.0) * w;
  const double f = spring + dash;
  return (!tension && f < 0) ? 0.0 : -f;
}

}  // namespace

double restitution_for_damping(double beta, bool hertz, bool tension) {
  // Classical RK4 on (u, w) from first touch at unit speed until the overlap closes again.
  // The contact lasts about pi (linear) or 3.2 (Hertz) in these units.
  const double h = 2e-4;
  double u = 0, w = 1;
  for (int step = 0; step < 1000000; ++step) {
    const double k1u = w, k1w = accel(u, w, beta, hertz, tension);
    const double k2u = w + 0.5 * h * k1w, k2w = accel(u + 0.5 * h * k1u, k2u, beta, hertz, tension);
    const double k3u = w + 0.5 * h * k2w, k3w = accel(u + 0.5 * h * k2u, k3u, beta, hertz, tension);
    const double k4u = w + h * k3w, k4w = accel(u + h * k3u, k4u, beta, hertz, tension);
    const double un = u + h / 6 * (k1u + 2 * k2u + 2 * k3u + k4u);
    const double wn = w + h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w);
    if (un <= 0 && step > 0) {
      // Separation inside this step: interpolate the speed linearly at u = 0.
      const double s = u / (u - un);
      return -(w + s * (wn - w));
    }
    if (wn >= 0 && un > 0 && w < 0) return 0;  // came to rest in contact: fully inelastic
    u = un;
    w = wn;
  }
  return 0;
}

double restitution_damping(double e, bool hertz, bool tension) {
  if (e >= 1) return 0;
  if (!hertz && tension) {
    const double l = std::log(e);
    return -2 * l / std::sqrt(M_PI * M_PI + l * l);
  }
  // Restitution falls monotonically with beta: bisect.
  double lo = 0, hi = 1;
  while (restitution_for_damping(hi, hertz, tension) > e) hi *= 2;
  for (int it = 0; it < 60 && hi - lo > 1e-10 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (restitution_for_damping(mid, hertz, tension) > e ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace kiln::contact
