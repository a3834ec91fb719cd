#include "src/exact_solutions.h"

#include <cmath>

#include "contact/normal_force.h"
#include "src/dem_system.h"
#include "thermal/conductance.h"

namespace kiln {

namespace {

// One disc and a floor at y = 0 with the linear spring-dashpot and gravity (T1, the harmonic
// contact): free flight and contact phases in closed form, one after the other.
// Contact: overlap d = r - y obeys d'' + 2 zeta w d' + w^2 d = g, a damped oscillator about
// g / w^2; flight: y'' = -g.
std::pair<double, double> disc_on_floor(const Scene& s, double t_end) {
  const double r = s.radius[0], g = -s.gravity.y;
  const double m = disc_mass(s, r, s.materials[s.material[0]].density);
  const int wall_material = s.walls.front().material;
  const PairLaw& law = s.law(s.material[0], wall_material);
  const double w = std::sqrt(law.stiffness / m);
  const double zeta = contact::restitution_damping(law.restitution, false, true) / 2;
  const double wd = w * std::sqrt(1 - zeta * zeta);
  double t = 0, y = s.position[0].y, v = s.velocity[0].y;
  while (true) {
    if (y > r || v > 0) {
      // Flight until the disc touches (y = r again), or the end.
      const double land = (v + std::sqrt(v * v + 2 * g * (y - r))) / g;
      if (t + land >= t_end) {
        const double tau = t_end - t;
        return {y + v * tau - 0.5 * g * tau * tau, v - g * tau};
      }
      t += land;
      v -= g * land;
      y = r;
    }
    // Contact from overlap r - y with rate -v, until the overlap returns to zero, or the end.
    const double eq = g / (w * w), a = (r - y) - eq, rate = -v;
    const double b = (rate + zeta * w * a) / wd;
    auto overlap = [&](double tau) {
      return eq + std::exp(-zeta * w * tau) * (a * std::cos(wd * tau) + b * std::sin(wd * tau));
    };
    auto overlap_rate = [&](double tau) {
      return std::exp(-zeta * w * tau) *
             ((-zeta * w * a + wd * b) * std::cos(wd * tau) + (-zeta * w * b - wd * a) * std::sin(wd * tau));
    };
    const double left = t_end - t, step = M_PI / wd / 64;
    double lo = 0, hi = 0;
    bool opens = false;
    while (!opens && hi < left) {
      lo = hi;
      hi = std::min(left, hi + step);
      opens = overlap(hi) < 0;
    }
    if (!opens) return {r - overlap(left), -overlap_rate(left)};
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (overlap(mid) >= 0 ? lo : hi) = mid;
    }
    t += lo;
    y = r;
    v = -overlap_rate(lo);
  }
}

}  // namespace

std::optional<std::vector<double>> exact_quantity(const Scene& s, const std::string& q, double t) {
  if ((s.name == "t1_free_fall" || s.name == "t1_free_fall_damped" || s.name == "harmonic_contact_pair") &&
      (q == "position" || q == "velocity")) {
    const auto [y, v] = disc_on_floor(s, t);
    return q == "position" ? std::vector<double>{s.position[0].x, y} : std::vector<double>{s.velocity[0].x, v};
  }
  if ((s.name == "t4_two_particle_conduction" || s.name == "f2_pipe_network_pair") && q == "temperature") {
    // Two bodies through one constant conductance: the difference decays as
    // exp(-H (1/C_A + 1/C_B) t), the capacity-weighted mean stays.
    const Material &ma = s.materials[s.material[0]], &mb = s.materials[s.material[1]];
    const double ca = disc_mass(s, s.radius[0], ma.density) * ma.specific_heat;
    const double cb = disc_mass(s, s.radius[1], mb.density) * mb.specific_heat;
    const PairLaw& law = s.law(s.material[0], s.material[1]);
    const thermal::ConductionLaw cl{law.conduction, ma.conductivity, mb.conductivity, law.conductance, law.modulus_ratio,
                                    law.effective_modulus, s.thickness, law.contact_resistance};
    const double d = norm(s.position[1] - s.position[0]);
    const double h = thermal::conductance(cl, s.radius[0], s.radius[1], d, 0);
    const double mean = (ca * s.temperature[0] + cb * s.temperature[1]) / (ca + cb);
    const double diff = (s.temperature[0] - s.temperature[1]) * std::exp(-h * (1 / ca + 1 / cb) * t);
    return std::vector<double>{mean + diff * cb / (ca + cb), mean - diff * ca / (ca + cb)};
  }
  if (s.name == "c1_incline_roll_slide" && q == "incline_acceleration") {
    // Rolling without slip when tan(theta) <= mu (1 + m r^2 / I), else sliding.
    const double along = s.gravity.x, normal = -s.gravity.y;
    const double inertia_ratio = s.mass_model == MassModel::sphere ? 0.4 : 0.5;  // I / (m r^2)
    const double mu = s.law(s.material[0], s.walls.front().material).friction;
    const bool rolls = along / normal <= mu * (1 + 1 / inertia_ratio);
    return std::vector<double>{rolls ? along / (1 + inertia_ratio) : along - mu * normal};
  }
  return std::nullopt;
}

std::string exact_solutions_known() {
  return "position and velocity of t1_free_fall, t1_free_fall_damped, harmonic_contact_pair; temperature of "
         "t4_two_particle_conduction, f2_pipe_network_pair; incline_acceleration of c1_incline_roll_slide";
}

}  // namespace kiln
