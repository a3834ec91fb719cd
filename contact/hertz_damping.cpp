// Restitution <-> dashpot coefficient for the normal laws (see normal_force.h).
#include <algorithm>
#include <cmath>

#include "contact/normal_force.h"

namespace kiln::contact {

namespace {

// Dimensionless relative acceleration u'' for overlap u and rate w = u', the contact law
// continued smoothly to u < 0 (odd extension) so that the step that crosses separation is
// integrated on a smooth right-hand side; the crossing itself is then interpolated.
double accel(double u, double w, double beta, bool hertz, bool tension) {
  const double m = std::abs(u);
  const double spring = hertz ? std::copysign(m * std::sqrt(m), u) : u;
  const double dash = beta * (hertz ? std::sqrt(std::sqrt(m)) : 1.0) * w;
  const double f = spring + dash;
  return (!tension && f < 0) ? 0.0 : -f;
}

}  // namespace

double restitution_for_damping(double beta, bool hertz, bool tension) {
  // Classical RK4 on (u, w) from first touch at unit speed until the overlap closes again.
  // The contact lasts about pi (linear) or 3.2 (Hertz) in these units. The separation instant
  // inside the last step is found on the cubic Hermite interpolant of u (Newton), and the speed
  // there from the Hermite interpolant of w, keeping the fourth-order accuracy of the steps.
  const double h = 1e-4;
  double u = 0, w = 1, a = accel(u, w, beta, hertz, tension);
  for (int step = 0; step < 10000000; ++step) {
    const double k1u = w, k1w = a;
    const double k2u = w + 0.5 * h * k1w, k2w = accel(u + 0.5 * h * k1u, k2u, beta, hertz, tension);
    const double k3u = w + 0.5 * h * k2w, k3w = accel(u + 0.5 * h * k2u, k3u, beta, hertz, tension);
    const double k4u = w + h * k3w, k4w = accel(u + h * k3u, k4u, beta, hertz, tension);
    const double un = u + h / 6 * (k1u + 2 * k2u + 2 * k3u + k4u);
    const double wn = w + h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w);
    if (un <= 0 && step > 0) {
      const double an = accel(0, wn, beta, hertz, tension);
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
    u = un;
    w = wn;
    a = accel(u, w, beta, hertz, tension);
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
