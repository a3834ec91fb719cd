#include "src/studies/exact_solutions.h"

#include <cmath>

#include "contact/normal_force.h"
#include "src/dem/contact_coefficients.h"
#include "src/dem/dem_system.h"
#include "src/run/simulation.h"
#include "src/studies/network_exact.h"

namespace kiln {

namespace {

// The overlap of a linear spring-dashpot contact with a constant load:
// d'' + 2 zeta w d' + w^2 d = w^2 eq (underdamped), from d(0) = d0 and d'(0) = rate0.
struct DampedOscillator {
  double eq, zeta, w, wd, a, b;
  DampedOscillator(double eq_, double zeta_, double w_, double d0, double rate0)
      : eq(eq_), zeta(zeta_), w(w_), wd(w_ * std::sqrt(1 - zeta_ * zeta_)), a(d0 - eq_),
        b((rate0 + zeta_ * w_ * (d0 - eq_)) / wd) {}
  double value(double tau) const {
    return eq + std::exp(-zeta * w * tau) * (a * std::cos(wd * tau) + b * std::sin(wd * tau));
  }
  double rate(double tau) const {
    return std::exp(-zeta * w * tau) *
           ((-zeta * w * a + wd * b) * std::cos(wd * tau) + (-zeta * w * b - wd * a) * std::sin(wd * tau));
  }
};

// One disc and a floor at y = 0 with the linear spring-dashpot and gravity (T1, the harmonic
// contact): free flight and contact phases in closed form, one after the other.
// Contact: overlap d = r - y obeys d'' + 2 zeta w d' + w^2 d = g, a damped oscillator about
// g / w^2; flight: y'' = -g.
std::pair<double, double> disc_on_floor(const Scene& s, double t_end) {
  const double r = s.radius[0], g = -s.gravity.y;
  const double m = disc_mass(s, r, s.materials[s.material[0]].density);
  const int wall_material = s.walls.front().material;
  const contact::NormalLaw nl = contact_coefficients(s, s.material[0], wall_material).normal_law(m, r);
  const double w = std::sqrt(nl.k / m);
  const double zeta = nl.c / (2 * std::sqrt(m * nl.k));
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
    const DampedOscillator contact(g / (w * w), zeta, w, r - y, -v);
    auto overlap = [&](double tau) { return contact.value(tau); };
    auto overlap_rate = [&](double tau) { return contact.rate(tau); };
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

// One disc on a flat horizontal floor with the linear law and Coulomb friction (the 2/7 stick
// impact, the oblique impact in gross sliding, slide-to-roll, C1 rolling from rest), in closed
// form piece by piece. The floor is kiln's wall contact: normal n = (0, -1) from the disc to the
// floor, tangent t = perp(n) = (1, 0), lever arm the full radius r, so the slip of the contact
// point is s = v_x + r omega and the tangential force F_t (along x) gives the torque r F_t.
//   normal:     m delta'' = m g_n - F_n,  F_n = k delta + c delta'   (delta = overlap, g_n = -g_y)
//   tangential: m v_x' = m g_x + F_t,  I omega' = r F_t,  so s' = g_x + kappa F_t / m with
//               kappa = 1 + m r^2 / I (7/2 for a sphere, 3 for a cylinder), and
//               m r (v_x - g_x t) - I omega is constant through every phase.
//   stick:      F_t = -k_t xi - c_t s with xi' = s, a forced damped oscillator in xi,
//               xi'' = g_x - kappa (k_t xi + c_t xi') / m, omega_t^2 = kappa k_t / m;
//   slide:      F_t = -sigma mu F_n, sigma the sign of the trial force's opposite; the spring
//               carries the capped force, xi = sigma mu F_n / k_t. Since m delta'' = m g_n - F_n,
//               the integral of F_n is m (g_n tau - (delta'(tau) - delta'(0))): closed form.
// Phases end where a closed form crosses zero (overlap: release; mu F_n - |trial force|: stick to
// slide; sigma s: slide to stick), found by scanning 1/256 of a period and bisecting to round-off.
// A fresh contact's spring starts at xi = 0, so even a disc that slides has a short loading phase
// in stick first (slide_to_roll): that is the model's exact solution, not the rigid-body one.
// Returns nothing for what the closed forms do not cover (several particles or walls, a floor that
// is not horizontal or moves, Hertz, rolling resistance, a tensile force while sliding, overdamped
// springs).
struct FloorDiscState {
  double x = 0, y = 0, vx = 0, vy = 0, omega = 0;
};

std::optional<FloorDiscState> friction_disc_on_floor(const Scene& s, double t_end) {
  if (s.n_particles() != 1 || s.walls.size() != 1 || s.segments.size() != 1) return std::nullopt;
  const Segment& seg = s.segments[0];
  const contact::ContactLaw& law = s.law(s.material[0], s.walls[0].material).contact;
  if (seg.a.y != seg.b.y || s.walls[0].motion.moves() || law.model != contact::NormalModel::linear ||
      law.rolling_friction > 0)
    return std::nullopt;
  const double r = s.radius[0], floor = seg.a.y;
  const double m = disc_mass(s, r, s.materials[s.material[0]].density), inertia = disc_inertia(s, m, r);
  const double kappa = 1 + m * r * r / inertia;
  const contact::NormalLaw nl = contact_coefficients(s, s.material[0], s.walls[0].material).normal_law(m, r);
  const double k = nl.k, c = nl.c;
  if (!law.tension && c > 0) return std::nullopt;  // the clamped dashpot is not linear
  const double kt = law.tangential_stiffness_ratio * k, ct = law.tangential_damping_ratio * c, mu = law.friction;
  const double gx = s.gravity.x, gn = -s.gravity.y;
  const double w = std::sqrt(k / m), zeta = c / (2 * m * w);
  const double wt = std::sqrt(kappa * kt / m), zeta_t = kappa * ct / (2 * m * wt);
  if (!(zeta < 1) || !(zeta_t < 1)) return std::nullopt;
  const double wd = w * std::sqrt(1 - zeta * zeta), wtd = wt * std::sqrt(1 - zeta_t * zeta_t);
  const double scan = std::min(M_PI / wd, mu > 0 ? M_PI / wtd : INFINITY) / 256;

  // The first tau in (0, left] where f turns negative (f(0) >= 0 is assumed), or -1 if none:
  // scanned, then bisected to round-off.
  auto first_negative = [&](const auto& f, double left) {
    double lo = 0, hi = 0;
    while (hi < left) {
      lo = hi;
      hi = std::min(left, hi + scan);
      if (f(hi) < 0) {
        for (int it = 0; it < 200 && hi - lo > 0; ++it) {
          const double mid = 0.5 * (lo + hi);
          if (mid == lo || mid == hi) break;
          (f(mid) < 0 ? hi : lo) = mid;
        }
        return hi;
      }
    }
    return -1.0;
  };

  FloorDiscState st{s.position[0].x, s.position[0].y, s.velocity[0].x, s.velocity[0].y, s.angular_velocity[0]};
  const double invariant_base = m * r * st.vx - inertia * st.omega;  // m r (v_x - g_x t) - I omega
  double t = 0;
  auto finish = [&](double vx_now) {
    st.vx = vx_now;
    st.omega = (m * r * (st.vx - gx * t) - invariant_base) / inertia;
    return st;
  };
  while (true) {
    double delta = r - (st.y - floor);
    // Flight until the disc touches the floor (moving into it), or the end.
    if (delta < 0 || (delta == 0 && st.vy >= 0 && !(gn > 0 && st.vy == 0))) {
      const double gap = st.y - floor - r;  // >= 0
      if (gn < 0) return std::nullopt;  // gravity away from the floor: not needed
      double land = INFINITY;
      if (gn > 0) land = (st.vy + std::sqrt(st.vy * st.vy + 2 * gn * gap)) / gn;
      else if (st.vy < 0) land = gap / -st.vy;
      const double tau = std::min(land, t_end - t);
      st.x += st.vx * tau + 0.5 * gx * tau * tau;
      st.vx += gx * tau;
      st.y += st.vy * tau - 0.5 * gn * tau * tau;
      st.vy -= gn * tau;
      t += tau;
      if (t >= t_end) return finish(st.vx);
      st.y = floor + r;
      delta = 0;
    }
    // Contact from overlap delta0 with rate delta_rate0: the normal motion in closed form.
    const DampedOscillator contact(gn / (w * w), zeta, w, delta, -st.vy);
    auto overlap = [&](double tau) { return contact.value(tau); };
    auto overlap_rate = [&](double tau) { return contact.rate(tau); };
    auto normal = [&](double tau) { return k * overlap(tau) + c * overlap_rate(tau); };
    const double release = first_negative(overlap, t_end - t);  // -1: lasts past the end
    const double contact_end = release < 0 ? t_end - t : release;
    // The tangential motion, sub-phase by sub-phase, from tau0 (time since the contact began).
    double tau0 = 0, x0 = st.x, vx0 = st.vx, xi0 = 0, s0 = st.vx + r * st.omega;
    if (mu == 0) {  // frictionless: the tangential motion is free
      const double tau = contact_end;
      st.x += st.vx * tau + 0.5 * gx * tau * tau;
      st.vx += gx * tau;
    } else {
      const double t_contact = t;
      int phases = 0;
      while (tau0 < contact_end) {
        // Stick from (xi0, s0): xi = xi_p + e^(-zeta_t wt u) (A cos(wtd u) + B sin(wtd u)).
        const double xi_p = gx * m / (kappa * kt), A = xi0 - xi_p, B = (s0 + zeta_t * wt * A) / wtd;
        auto xi = [&](double u) {
          return xi_p + std::exp(-zeta_t * wt * u) * (A * std::cos(wtd * u) + B * std::sin(wtd * u));
        };
        auto slip = [&](double u) {
          return std::exp(-zeta_t * wt * u) *
                 ((-zeta_t * wt * A + wtd * B) * std::cos(wtd * u) + (-zeta_t * wt * B - wtd * A) * std::sin(wtd * u));
        };
        auto trial = [&](double u) { return kt * xi(u) + ct * slip(u); };  // -F_t in stick
        // Holds while |trial| <= mu F_n; a tolerance of round-off lets the force touch the cap
        // (slide_to_roll's spring reaches it again, with zero slip, every rocking period).
        auto holds = [&](double u) {
          const double cap = mu * std::max(normal(tau0 + u), 0.0);
          return cap - std::abs(trial(u)) + 1e-12 * (cap + std::abs(trial(u)));
        };
        const double left = contact_end - tau0, probe = 1e-4 / std::max(w, wt);
        if (holds(std::min(probe, left)) >= 0) {
          const double slide_at = first_negative(holds, left);
          const double u = slide_at < 0 ? left : slide_at;
          const double s_u = slip(u), xi_u = xi(u);
          st.x = x0 + vx0 * u + 0.5 * gx * u * u + (xi_u - xi0 - s0 * u - 0.5 * gx * u * u) / kappa;
          st.vx = vx0 + gx * u + (s_u - s0 - gx * u) / kappa;
          tau0 += u;
          if (slide_at < 0) break;
          x0 = st.x, vx0 = st.vx, xi0 = xi_u, s0 = s_u;
          if (++phases > 10000) return std::nullopt;
          continue;
        }
        // Slide with F_t = -sigma mu F_n (the trial force's direction), from the same start.
        const double sigma = trial(std::min(probe, left)) >= 0 ? 1.0 : -1.0;
        const double d0 = overlap(tau0), r0 = overlap_rate(tau0), start = tau0;
        auto vx_slide = [&](double u) { return vx0 + gx * u - sigma * mu * (gn * u - (overlap_rate(start + u) - r0)); };
        auto slip_slide = [&](double u) { return s0 + gx * u + kappa * (vx_slide(u) - vx0 - gx * u); };
        const double round_off = 1e-12 * k * (std::abs(contact.eq) + std::abs(contact.a) + std::abs(contact.b));
        auto pressing = [&](double u) { return normal(start + u) + round_off; };
        if (first_negative(pressing, left) >= 0) return std::nullopt;  // tension while sliding
        // Sliding goes on while the stick law's trial force would pass the cap: with a tangential
        // dashpot (trial = cap + c_t |s|) until the slip stops; without one (trial = cap) while the
        // spring would load faster than the cap grows, sigma k_t s > mu dF_n/dt.
        auto keeps_sliding = [&](double u) {
          if (ct > 0) return sigma * slip_slide(u);
          const double tau = start + u, rate = k * overlap_rate(tau) + c * (gn - normal(tau) / m);
          return sigma * kt * slip_slide(u) - mu * rate;
        };
        const double stick_at = first_negative(keeps_sliding, left);
        const double u = stick_at < 0 ? left : stick_at;
        st.x = x0 + vx0 * u + 0.5 * gx * u * u - sigma * mu * (0.5 * gn * u * u - (overlap(start + u) - d0) + r0 * u);
        st.vx = vx_slide(u);
        tau0 += u;
        if (stick_at < 0) break;
        x0 = st.x, vx0 = st.vx, xi0 = sigma * mu * normal(tau0) / kt, s0 = slip_slide(u);
        if (++phases > 10000) return std::nullopt;  // chattering: no closed form worth having
      }
      t = t_contact;
    }
    t += contact_end;
    st.y = floor + r - overlap(contact_end);
    st.vy = -overlap_rate(contact_end);
    if (release < 0 || t >= t_end) return finish(st.vx);
    st.y = floor + r;  // released: the next phase is flight
    st.omega = (m * r * (st.vx - gx * t) - invariant_base) / inertia;
    if (st.vy < 0) st.vy = 0;
  }
}

// A thermal scene with frozen mechanics is a linear network with constant conductances
// (src/studies/network_exact.h). This covers T4, F1, F2, N1, and the heating stage of N2 and T5.
std::optional<std::vector<double>> frozen_network_temperatures(const Scene& s, double t) {
  std::vector<double> wall_temperature(s.walls.size(), 0.0);
  for (size_t w = 0; w < s.walls.size(); ++w) {
    const thermal::WallTemperature& wt = s.walls[w].temperature;
    if (!wt.isothermal()) continue;
    for (double v : wt.values)
      if (v != wt.values.front()) return std::nullopt;  // a schedule: no closed form here
    wall_temperature[w] = wt.values.front();
  }
  DemSystem system(s);
  std::vector<double> y = system.initial_state();
  std::vector<double> start = s.temperature;
  double frozen_at = 0;
  if (!s.frozen) {
    // A scene that freezes: the network is the settled one, reached by running the scene (with its
    // own integrator) to its freeze, and heated from the temperatures it has there.
    FinalFields settled;
    RunOptions options;
    options.quiet = true;
    options.final_fields = &settled;
    options.stop_at_freeze = true;
    const nlohmann::json summary = run_scene(s, options);
    if (!summary["frozen_at"].is_number() || summary["frozen_at"].get<double>() > t) return std::nullopt;
    frozen_at = summary["frozen_at"].get<double>();
    std::copy(settled.position.begin(), settled.position.end(), y.begin() + system.x_at());
    start = settled.temperature;
  }
  system.prepare(frozen_at, y.data(), 0);
  std::vector<double> capacity;
  for (int i = 0; i < system.particles(); ++i) capacity.push_back(system.heat_capacity(i));
  return thermal::exact_network_temperatures(system.conduction_links(frozen_at, y.data()), capacity,
                                             wall_temperature, start, t - frozen_at);
}

}  // namespace

std::optional<std::vector<double>> exact_quantity(const Scene& s, const std::string& q, double t) {
  if ((s.name == "t1_free_fall" || s.name == "t1_free_fall_damped" || s.name == "harmonic_contact_pair") &&
      (q == "position" || q == "velocity")) {
    const auto [y, v] = disc_on_floor(s, t);
    return q == "position" ? std::vector<double>{s.position[0].x, y} : std::vector<double>{s.velocity[0].x, v};
  }
  if ((s.name == "stick_two_sevenths" || s.name == "oblique_sliding_impact" || s.name == "slide_to_roll" ||
       s.name == "c1_incline_roll_slide") &&
      (q == "position" || q == "velocity")) {
    if (const auto st = friction_disc_on_floor(s, t))
      return q == "position" ? std::vector<double>{st->x, st->y} : std::vector<double>{st->vx, st->vy};
    return std::nullopt;
  }
  if (s.thermal && (s.frozen || s.freeze.enabled) && q == "temperature") {
    if (auto T = frozen_network_temperatures(s, t)) return T;
  }
  if (s.name == "c1_incline_roll_slide" && q == "incline_acceleration") {
    // Rolling without slip when tan(theta) <= mu (1 + m r^2 / I), else sliding.
    const double along = s.gravity.x, normal = -s.gravity.y;
    const double inertia_ratio = s.mass_model == MassModel::sphere ? 0.4 : 0.5;  // I / (m r^2)
    const double mu = s.law(s.material[0], s.walls.front().material).contact.friction;
    const bool rolls = along / normal <= mu * (1 + 1 / inertia_ratio);
    return std::vector<double>{rolls ? along / (1 + inertia_ratio) : along - mu * normal};
  }
  return std::nullopt;
}

std::string exact_solutions_known() {
  return "position and velocity of t1_free_fall, t1_free_fall_damped, harmonic_contact_pair, stick_two_sevenths, "
         "oblique_sliding_impact, slide_to_roll and c1_incline_roll_slide (one disc, one flat floor); temperature of "
         "every thermal scene with frozen mechanics and constant wall temperatures (t4, f1, f2, n1), and of "
         "the heating stage of a scene that freezes (n2, t5: from the state at its freeze); "
         "incline_acceleration of c1_incline_roll_slide";
}

}  // namespace kiln
