#include "src/run/stability.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <sstream>
#include <tuple>

#include "contact/in_series.h"
#include "contact/normal_force.h"
#include "src/dem/contact_coefficients.h"
#include "src/dem/dem_system.h"
#include "src/base/progress.h"
#include "src/base/wall_clock.h"
#include "src/dem/frozen_conduction.h"
#include "integrators/stability_region.h"
#include "src/run/linearised_dynamics.h"

namespace kiln {

namespace {

// The highest speeds at which a disc can meet a wall and another disc: a disc moves at most at its
// largest initial speed (random_velocity included) plus, with walls, a free fall over the scene's
// height along g plus the largest speed of a moving wall (a wall pushes it: WallMotion::largest_speed, a
// load-controlled wall's driven speed included, and its fall along its load), and two discs can approach each other at twice
// that. Speeds are taken with hypot, which does not overflow below 1.8e308; a bound that is still
// not finite (speeds or g near the largest double) is refused by judge_dt.
struct ImpactSpeeds {
  double wall = 0, pair = 0;
};

double speed(Vec2 v) { return std::hypot(v.x, v.y); }

// How far the scene (its particles and wall segments) extends along the unit direction `along` (m).
double extent_along(const Scene& scene, Vec2 along) {
  double lo = INFINITY, hi = -INFINITY;
  for (const Vec2 p : scene.position) lo = std::min(lo, dot(p, along)), hi = std::max(hi, dot(p, along));
  for (const Segment& s : scene.segments)
    lo = std::min({lo, dot(s.a, along), dot(s.b, along)}), hi = std::max({hi, dot(s.a, along), dot(s.b, along)});
  return std::max(0.0, hi - lo);
}

ImpactSpeeds impact_speeds(const Scene& scene) {
  const double g = speed(scene.gravity);
  const Vec2 down = g > 0 ? Vec2{scene.gravity.x / g, scene.gravity.y / g} : Vec2{0, -1};
  double v0 = 0;
  for (const Vec2 v : scene.velocity) v0 = std::max(v0, speed(v));
  double wall_speed = 0;
  for (size_t w = 0; w < scene.walls.size(); ++w) {
    const WallMotion& motion = scene.walls[w].motion;
    wall_speed = std::max(wall_speed, motion.largest_speed(scene.segments, static_cast<int>(w)));
    // A load-controlled wall also falls along its load, at most across the scene, as a disc falls
    // under gravity: a load of 1e300 N passed check and the run died of NaN blaming dt (issue 28's
    // review).
    const double load = speed(motion.load);
    if (motion.kind != WallMotion::Kind::load_controlled || !(load > 0)) continue;
    const double span = extent_along(scene, {motion.load.x / load, motion.load.y / load});
    wall_speed = std::max(wall_speed, std::sqrt(2 * (load / motion.mass)) * std::sqrt(span));
  }
  // Gravity speeds every disc up alike: it adds to an impact only against a wall, and against a
  // disc that a wall threw back. Without walls discs meet at their initial speeds.
  const bool walls = !scene.segments.empty();
  const double fall = walls ? std::sqrt(2 * g) * std::sqrt(extent_along(scene, down)) : 0.0;
  const double disc = v0 + fall + wall_speed;
  return {std::max(disc, 1e-3), std::max(2 * disc, 1e-3)};
}

}  // namespace

std::optional<std::string> too_many_steps(const char* step_name, double step, double duration,
                                          const char* duration_name) {
  const double steps = std::ceil(duration / step);
  if (steps <= max_steps) return std::nullopt;
  std::ostringstream s;
  s << duration_name << " / " << step_name << " = " << duration << " s / " << step << " s = " << steps
    << " steps, more than the limit of " << max_steps << " steps: the run would not end in any useful time; raise "
    << step_name << " or shorten " << duration_name << ", or run it anyway with --force";
  return s.str();
}

std::optional<std::string> too_many_moving_steps(const Scene& scene, double dt, double t_end) {
  if (scene.freeze.enabled && scene.freeze.latest < t_end)
    return too_many_steps("dt", dt, scene.freeze.latest, "freeze.latest");
  return too_many_steps("dt", dt, t_end);
}

namespace {

// Estimates that are not numbers (NaN) come from masses, stiffnesses or speeds that overflow
// double precision; every comparison with them would pass.
bool not_a_number(const StabilityEstimate& e) {
  return std::isnan(e.contact_duration) || std::isnan(e.dt_limit) || std::isnan(e.rayleigh) ||
         std::isnan(e.thermal_dt_limit) || std::isnan(e.thermal_dt_limit_network);
}

void thermal_estimate(const Scene& scene, const std::vector<double>& rmin, const std::vector<int>& count,
                      StabilityEstimate& est) {
  DemSystem system(scene);
  const std::vector<double> y = system.initial_state();
  system.prepare(0, y.data(), 0);
  std::vector<double> capacity;
  for (int i = 0; i < system.particles(); ++i) capacity.push_back(system.heat_capacity(i));
  const thermal::FrozenConduction network(system.conduction_links(0, y.data()), capacity, {}, system.ledger_count());
  double lambda = network.stiffest_rate();
  est.thermal_dt_limit_network = lambda > 0 || std::isnan(lambda) ? 2 / lambda : INFINITY;  // NaN is refused
  if (!scene.frozen) {
    // Dense packing of the smallest particles of each material pair at 1 % overlap.
    const int nm = scene.n_materials();
    for (int a = 0; a < nm; ++a)
      for (int b = 0; b < nm; ++b) {
        if (!count[a] || !count[b]) continue;
        const ContactCoefficients pair = contact_coefficients(scene, a, b);
        const double ra = rmin[a], rb = rmin[b], overlap = 0.01 * std::min(ra, rb);
        const double k = pair.normal_stiffness(contact::in_series(ra, rb));
        const double fn = contact::normal_force({k, 0, pair.law.model, true}, overlap, 0);
        const double h = thermal::conductance(pair.conduction, ra, rb, ra + rb - overlap, fn);
        const Material& ma = scene.materials[a];
        const double c = disc_mass(scene, ra, ma.density) * ma.specific_heat;
        // The largest eigenvalue of a triangular lattice's Laplacian: 9 h (six neighbours;
        // Gershgorin's bound is 12 h).
        const double rate = 9 * h / c;
        if (std::isnan(rate) || rate > lambda) lambda = rate;  // NaN kept, to be refused (max drops it)
      }
  }
  if (lambda > 0 || std::isnan(lambda)) {
    est.thermal_dt_limit = 2 / lambda;
    est.thermal_relaxation_time = 1 / lambda;
  }
}

}  // namespace

MechanicalLimit mechanical_limit(const DemSystem& system, double t, const double* y, const std::string& integrator,
                                 const std::string& state) {
  const IntegratorInfo& info = integrator_info(integrator);
  MechanicalLimit out;
  {  // gone before the uncapped springs' linearisation: one basis and one set of rows at a time
    const LinearisedMechanics m = linearise_mechanics(system, t, y);
    const StepLimit step = mechanical_step_limit(info, m.k, m.c);
    out.dt = step.dt;
    out.omega_max = m.omega_max;
    out.coordinates = m.coordinates;
    out.contacts = static_cast<int>(m.contacts.size());
    const ModeDescription d = describe_mode(m, step.shape, system.scene());
    out.mode = d.kind;
    out.where = d.where;
  }
  out.state = state;
  out.blow_up_dt = out.dt;
  // Measured (docs/stability_table.md): under the Verlet schemes such a mode saturates at its cap;
  // under the Runge-Kutta tables (erk4 on the slope disc at 1.05 of its limit) the run blows up
  // at the limit itself.
  if ((out.mode == "tangential-rotational" || out.mode == "rolling") && info.scheme != IntegratorScheme::arkode) {
    const LinearisedMechanics uncapped = linearise_mechanics(system, t, y, Springs::uncapped);
    out.blow_up_dt = std::max(out.dt, mechanical_step_limit(info, uncapped.k, uncapped.c).dt);
  }
  return out;
}

StabilityEstimate with_state(StabilityEstimate est, const MechanicalLimit& at_state) {
  const double blow_up = std::min(est.limit.blow_up_dt, at_state.blow_up_dt);
  if (at_state.dt < est.dt_limit) {
    est.limit = at_state;
    est.dt_limit = at_state.dt;
    est.recommended_dt = std::min(est.contact_duration / 50, est.dt_limit);
  }
  est.limit.blow_up_dt = std::max(est.dt_limit, blow_up);
  return est;
}

std::optional<MechanicalLimit> limit_at(const DemSystem& system, double t, const double* y, int size,
                                        const std::string& integrator, const std::string& what) {
  for (int k = 0; k < size; ++k)
    if (!std::isfinite(y[k])) return std::nullopt;
  try {
    std::ostringstream state;
    state << "the contacts at t = " << t << " s" << what;
    return mechanical_limit(system, t, y, integrator, state.str());
  } catch (const std::exception&) {  // an eigensolver that does not converge on a state blown apart
    return std::nullopt;
  }
}

namespace {

// The scene with its particles and segments replaced by one contact: two discs of radii ra, rb
// and materials a, b (wall < 0; the second held in place when `b_held`: a fixed or attached
// disc, which takes no forces), or a disc of radius ra and material a on segment `segment`, at
// `overlap`; at rest, in no periodic cell.
Scene lone_contact(const Scene& scene, int a, double ra, int b, double rb, int segment, double overlap,
                   bool b_held = false) {
  Scene probe = scene;
  probe.position.clear();
  probe.velocity.clear();
  probe.radius.clear();
  probe.angular_velocity.clear();
  probe.material.clear();
  probe.attached.clear();
  probe.periodic = {};
  probe.frozen = false;
  auto disc = [&](int material, double r, Vec2 at, int attached = Scene::free_particle) {
    probe.position.push_back(at);
    probe.velocity.push_back({0, 0});
    probe.radius.push_back(r);
    probe.angular_velocity.push_back(0);
    probe.material.push_back(material);
    probe.attached.push_back(attached);
  };
  probe.segments.clear();
  if (segment < 0) {
    disc(a, ra, {0, 0});
    disc(b, rb, {ra + rb - overlap, 0}, b_held ? Scene::fixed_particle : Scene::free_particle);
  } else {
    Segment s = scene.segments[segment];
    s.prev = -1;
    s.next_shared = false;
    probe.segments.push_back(s);
    const Vec2 along = s.b - s.a, middle = 0.5 * (s.a + s.b);
    const Vec2 normal = (1 / norm(along)) * perp(along);
    disc(a, ra, middle + (ra - overlap) * normal);
  }
  if (probe.thermal) probe.temperature.assign(probe.radius.size(), scene.temperature.front());
  return probe;
}

// The probe's limit, its place named `where` (the probe's own particle indices mean nothing in
// the scene).
MechanicalLimit probe_limit(const Scene& probe, const std::string& integrator, const std::string& state,
                            const std::string& where) {
  DemSystem system(probe);
  const std::vector<double> y = system.initial_state();
  system.prepare(0, y.data(), 0);
  MechanicalLimit l = mechanical_limit(system, 0, y.data(), integrator, state);
  if (l.mode != "wall body") l.where = where;
  return l;
}

// f(a, b, m_eff, r_eff) for each pair of materials a <= b the scene can bring together, as their
// smallest particles (count: particles per material; a material with itself needs two).
template <class F>
void for_each_material_pair(const Scene& scene, const std::vector<double>& rmin, const std::vector<int>& count, F f) {
  const int nm = scene.n_materials();
  for (int a = 0; a < nm; ++a)
    for (int b = a; b < nm; ++b) {
      if (!count[a] || !count[b] || (a == b && count[a] < 2)) continue;
      const double mass_a = disc_mass(scene, rmin[a], scene.materials[a].density);
      const double mass_b = disc_mass(scene, rmin[b], scene.materials[b].density);
      f(a, b, contact::in_series(mass_a, mass_b), contact::in_series(rmin[a], rmin[b]));
    }
}

// The overlap a lone contact reaches: a Hertz spring's at the impact speed (its stiffness grows
// with it), 1 % of the smaller radius for a linear one (whose slope does not depend on it).
double probe_overlap(const Scene& scene, int a, int b, double m_eff, double r_eff, double r_small, double speed) {
  const ContactCoefficients pair = contact_coefficients(scene, a, b);
  if (pair.law.model != contact::NormalModel::hertz) return 0.01 * r_small;
  const double k = pair.normal_stiffness(r_eff);
  return std::min(0.5 * r_small, std::pow(1.25 * m_eff * speed * speed / k, 0.4));
}

// The start's contacts, and the lone contacts free particles can form: with each other, with a
// held (fixed or attached) particle, whose mass does not count, and with each wall. Two held
// particles never meet.
MechanicalLimit scene_limit(const Scene& scene, const std::string& integrator, const ImpactSpeeds& speeds,
                            PhaseProgress& progress) {
  const int nm = scene.n_materials();
  std::vector<double> rmin(nm, INFINITY), rheld(nm, INFINITY);  // smallest free and held radius per material
  std::vector<int> count(nm, 0), held(nm, 0);
  for (int i = 0; i < scene.n_particles(); ++i) {
    const int m = scene.material[i];
    if (scene.attached[i] == Scene::free_particle) {
      rmin[m] = std::min(rmin[m], scene.radius[i]);
      ++count[m];
    } else {
      rheld[m] = std::min(rheld[m], scene.radius[i]);
      ++held[m];
    }
  }
  MechanicalLimit best;
  auto consider = [&](const MechanicalLimit& l) {  // a limit that is no number is kept, to be refused
    if (std::isnan(best.dt)) return;
    if (std::isnan(l.dt) || l.dt < best.dt || (std::isinf(best.dt) && best.state.empty())) best = l;
  };
  {
    progress.phase("the contacts at t = 0");
    DemSystem system(scene);
    const std::vector<double> y = system.initial_state();
    system.prepare(0, y.data(), 0);
    consider(mechanical_limit(system, 0, y.data(), integrator, "the contacts at t = 0"));
  }
  progress.phase("lone contacts of the smallest particles");
  for_each_material_pair(scene, rmin, count, [&](int a, int b, double m_eff, double r_eff) {
    const double overlap = probe_overlap(scene, a, b, m_eff, r_eff, std::min(rmin[a], rmin[b]), speeds.pair);
    consider(probe_limit(lone_contact(scene, a, rmin[a], b, rmin[b], -1, overlap), integrator,
                         "a lone " + scene.materials[a].name + "-" + scene.materials[b].name + " contact",
                         "the smallest free " + scene.materials[a].name + " and " + scene.materials[b].name +
                             " particles"));
  });
  for (int a = 0; a < nm; ++a) {
    if (!count[a]) continue;
    const Material& ma = scene.materials[a];
    const double mass_a = disc_mass(scene, rmin[a], ma.density);
    for (int b = 0; b < nm; ++b) {
      if (!held[b]) continue;
      const double r_eff = rmin[a] * rheld[b] / (rmin[a] + rheld[b]);
      const double overlap = probe_overlap(scene, a, b, mass_a, r_eff, std::min(rmin[a], rheld[b]), speeds.wall);
      consider(probe_limit(lone_contact(scene, a, rmin[a], b, rheld[b], -1, overlap, true), integrator,
                           "a lone " + ma.name + " contact with a held " + scene.materials[b].name + " particle",
                           "the smallest free " + ma.name + " particle on the smallest held " +
                               scene.materials[b].name + " one"));
    }
    for (size_t w = 0; w < scene.walls.size(); ++w) {
      int segment = -1;
      for (size_t s = 0; s < scene.segments.size() && segment < 0; ++s)
        if (scene.segments[s].wall == static_cast<int>(w)) segment = static_cast<int>(s);
      if (segment < 0) continue;
      const double overlap = probe_overlap(scene, a, scene.walls[w].material, mass_a, rmin[a], rmin[a], speeds.wall);
      consider(probe_limit(lone_contact(scene, a, rmin[a], -1, 0, segment, overlap), integrator,
                           "a lone " + ma.name + " contact with wall " + scene.walls[w].name,
                           "the smallest free " + ma.name + " particle on wall " + scene.walls[w].name));
    }
  }
  return best;
}

}  // namespace

StabilityEstimate estimate_stability(const Scene& scene, const std::string& integrator) {
  const auto start = std::chrono::steady_clock::now();
  // 10^7 discs: a minute, which `kiln check` spent without a word.
  PhaseProgress progress("estimating the stability limit", scene.n_particles() < progress_min_items);
  StabilityEstimate est;
  const ImpactSpeeds speeds = impact_speeds(scene);
  est.impact_speed = std::max(speeds.wall, speeds.pair);
  const int nm = scene.n_materials();
  // The smallest particle of each material gives the lightest pair.
  std::vector<double> rmin(nm, INFINITY);
  std::vector<int> count(nm, 0);
  for (int i = 0; i < scene.n_particles(); ++i) {
    rmin[scene.material[i]] = std::min(rmin[scene.material[i]], scene.radius[i]);
    ++count[scene.material[i]];
  }
  auto consider = [&](int a, int b, double m_eff, double r_eff, double speed, const std::string& label) {
    const contact::NormalLaw nl = contact_coefficients(scene, a, b).normal_law(m_eff, r_eff);
    const double duration = contact::contact_duration(nl, m_eff, speed);
    if (duration < est.contact_duration) {
      est.contact_duration = duration;
      est.shortest_pair = label;
    }
  };
  for_each_material_pair(scene, rmin, count, [&](int a, int b, double m_eff, double r_eff) {
    consider(a, b, m_eff, r_eff, speeds.pair, scene.materials[a].name + "-" + scene.materials[b].name);
  });
  for (int a = 0; a < nm; ++a) {
    if (!count[a]) continue;
    const Material& ma = scene.materials[a];
    const double mass_a = disc_mass(scene, rmin[a], ma.density);
    // A wall is of infinite mass, except a load-controlled wall body. It bears on as many contacts
    // as discs fit along it (and two for each disc attached to it), springs in parallel: its
    // fastest mode is that of its mass shared among them.
    for (size_t wi = 0; wi < scene.walls.size(); ++wi) {
      const Wall& w = scene.walls[wi];
      double m_wall = INFINITY;
      if (w.motion.free_along_load()) {
        double length = 0;
        for (const Segment& seg : scene.segments)
          if (seg.wall == static_cast<int>(wi)) length += norm(seg.b - seg.a);
        double contacts = std::max(1.0, std::floor(length / (2 * rmin[a])));
        for (int at : scene.attached) contacts += at == static_cast<int>(wi) ? 2 : 0;
        m_wall = w.motion.mass / contacts;
      }
      const double m_eff = std::isfinite(m_wall) ? contact::in_series(mass_a, m_wall) : mass_a;
      consider(a, w.material, m_eff, rmin[a], speeds.wall, ma.name + "-wall(" + w.name + ")");
    }
    if (ma.contact.youngs_modulus > 0) {
      const double shear = ma.contact.youngs_modulus / (2 * (1 + ma.contact.poisson_ratio));
      est.rayleigh = std::min(est.rayleigh, M_PI * rmin[a] * std::sqrt(ma.density / shear) /
                                                (0.1631 * ma.contact.poisson_ratio + 0.8766));
    }
  }
  if (!scene.frozen) {
    est.integrator = integrator.empty() ? scene.integrator : integrator;
    est.limit = scene_limit(scene, est.integrator, speeds, progress);
    est.dt_limit = est.limit.dt;
  }
  est.recommended_dt = std::min(est.contact_duration / 50, est.dt_limit);
  if (scene.thermal) {
    progress.phase("the conduction network at t = 0");
    thermal_estimate(scene, rmin, count, est);
    est.conduction_dt_limit =
        real_stability_of(integrator.empty() ? scene.integrator : integrator) / 2 * est.thermal_dt_limit_network;
  }
  est.seconds = seconds_since(start);
  return est;
}

namespace {

// Explicit conduction: certain for the network that exists at t = 0, an estimate otherwise.
// IMEX integrators take conduction implicitly and have no such limit.
// The limits are 2 / lambda_max (Euler, Heun, the Verlet schemes' temperatures), scaled by the
// integrator's reach along the negative real axis (RK4 2.79 / lambda_max; IMEX: none).
// dt lambda_max beyond which an implicit conduction stage is refused (judge_conduction).
constexpr double implicit_conditioning_limit = 1e13;

void judge_conduction(const StabilityEstimate& est, double dt, const Scene& scene, DtVerdict& v) {
  const double reach = real_stability_of(scene.integrator) / 2;
  const std::string& heating = scene.freeze.integrator.empty() ? scene.integrator : scene.freeze.integrator;
  const double heating_reach = real_stability_of(heating) / 2;
  std::ostringstream s;
  if (dt >= reach * est.thermal_dt_limit_network) {
    s << "dt = " << dt << " s is beyond " << scene.integrator << "'s explicit conduction limit "
      << reach * est.thermal_dt_limit_network << " s on the contact network (" << 2 * reach
      << " / lambda_max): the temperatures will blow up";
    v.unstable = true;
    v.warnings.push_back(s.str());
    return;
  }
  // An implicit stage solves (C + gamma dt G) T = b, whose condition number is about 1 + dt
  // lambda_max: beyond 1e13 the solve keeps fewer than three digits of double precision, and at
  // specific heat 1e-20 J/(kg K) on F2 the factorisation failed outright (an internal error, exit 6;
  // issue 28). Such a step is refused; so is its freeze.dt.
  const double lambda = 1 / est.thermal_relaxation_time;
  for (const auto& [name, step, stepper] : {std::tuple{"dt", dt, scene.integrator},
                                            std::tuple{"freeze.dt", scene.freeze.enabled ? scene.freeze.dt : 0.0, heating}})
    if (std::isinf(real_stability_of(stepper)) && step * lambda > implicit_conditioning_limit) {
      s << name << " = " << step << " s is " << step * lambda << " times the thermal relaxation time "
        << est.thermal_relaxation_time << " s: " << stepper << "'s implicit stages (C + gamma dt G) would be solved with "
        << "a condition number beyond " << implicit_conditioning_limit << ", fewer than three digits of double "
        << "precision (heat capacities this small equalise the temperatures at once); lower " << name << " below "
        << implicit_conditioning_limit * est.thermal_relaxation_time << " s";
      v.unstable = true;
      v.warnings.push_back(s.str());
      return;
    }
  if (dt >= reach * est.thermal_dt_limit) {
    s << "dt = " << dt << " s is beyond " << scene.integrator << "'s explicit conduction limit "
      << reach * est.thermal_dt_limit << " s on a dense packing at 1 % overlap: the temperatures may blow up once "
      << "contacts form";
    v.warnings.push_back(s.str());
  }
  if (scene.freeze.enabled && scene.freeze.dt >= heating_reach * est.thermal_dt_limit) {
    std::ostringstream w;
    w << "freeze.dt = " << scene.freeze.dt << " s is beyond " << heating << "'s explicit conduction limit "
      << heating_reach * est.thermal_dt_limit << " s on a dense packing at 1 % overlap (the settled network's "
      << "own limit is reported by the run as frozen_network.explicit_dt_limit)";
    v.warnings.push_back(w.str());
  }
}

void judge_mechanics(const StabilityEstimate& est, double dt, const Scene& scene, DtVerdict& v) {
  std::ostringstream s;
  // A step that carries a disc past another body by more than the smallest radius can jump over the
  // whole overlap band (2 r wide) without one evaluation inside it: the contact is never seen. It
  // needs another body: a second disc, or a wall.
  const double r_min = *std::min_element(scene.radius.begin(), scene.radius.end());
  const ImpactSpeeds speeds = impact_speeds(scene);
  const bool pairs = scene.n_particles() > 1, walls = !scene.segments.empty();
  const double approach = pairs ? speeds.pair : walls ? speeds.wall : 0.0;
  const MechanicalLimit& l = est.limit;
  if (!std::isfinite(approach)) {
    s << "the highest impact speed is not a finite number: initial speeds, gravity or wall speeds are too large "
      << "for double precision (about 1.8e308), so no dt carries a disc safely";
  } else if (dt * approach > r_min) {
    s << "dt x impact speed = " << dt << " s x " << approach << " m/s = " << dt * approach
      << " m is more than the smallest radius (" << r_min << " m): a disc can pass through a wall or another disc "
      << "between two steps; lower dt below " << r_min / approach << " s";
  } else if (l.dt > 0 && dt >= l.dt && scene.control.rtol > 0) {
    // An adaptive run's dt is its first trial step: the error controller shortens it.
    std::ostringstream w;
    w << "the first step dt = " << dt << " s is beyond " << est.integrator << "'s stability limit " << l.dt
      << " s on " << l.state << " (its " << l.mode << " mode, " << l.where << "): the step controller will shorten it";
    v.warnings.push_back(w.str());
  } else if (l.dt > 0 && dt >= l.dt && dt < l.blow_up_dt) {
    s << "dt = " << dt << " s is beyond " << est.integrator << "'s stability limit " << l.dt << " s on " << l.state
      << " (its " << l.mode << " mode, " << l.where << "): that mode grows until its spring reaches its "
      << (l.mode == "rolling" ? "rolling" : "Coulomb") << " cap, so sticking contacts creep or chatter instead of "
      << "sticking (the run blows up beyond " << l.blow_up_dt << " s, the normal modes' limit)";
  } else if (l.dt > 0 && dt >= l.dt) {
    s << "dt = " << dt << " s is beyond " << est.integrator << "'s stability limit " << l.dt << " s on " << l.state
      << " (its " << l.mode << " mode, " << l.where << "): the run will blow up";
  }
  if (!s.str().empty()) {
    v.unstable = true;
    v.warnings.push_back(s.str());
    return;
  }
  if (l.dt == 0) {
    s << est.integrator << " has no stable step on " << l.state << ": its " << l.mode << " mode (" << l.where
      << ") is undamped, and the method's stability region leaves out the imaginary axis near 0; the energy grows "
      << "by about (dt omega)^4 / 8 a step (see 'kiln integrators': a table with an imaginary interval, or a dashpot)";
    v.warnings.push_back(s.str());
    return;
  }
  if (!std::isfinite(est.contact_duration)) return;  // no contact can form: no step is too small or large
  const double per_contact = est.contact_duration / dt;
  if (per_contact < 20) {
    s << "only " << per_contact << " steps per contact (" << est.shortest_pair
      << "): expect large errors; 50 or more is usual (dt <= " << est.recommended_dt << " s)";
    v.warnings.push_back(s.str());
  } else if (per_contact > 20000) {
    s << per_contact << " steps per contact: dt could be much larger (" << est.recommended_dt << " s)";
    v.warnings.push_back(s.str());
  }
  if (std::isfinite(est.rayleigh) && dt > 0.3 * est.rayleigh) {
    std::ostringstream r;
    r << "dt is " << 100 * dt / est.rayleigh << " % of the Rayleigh time step; 10-30 % is usual";
    v.warnings.push_back(r.str());
  }
}

}  // namespace

std::string describe_limit(const StabilityEstimate& est) {
  const MechanicalLimit& l = est.limit;
  std::ostringstream s;
  if (est.integrator.empty()) return "mechanics frozen: no mechanical limit";
  if (std::isinf(l.dt)) return est.integrator + ": no contact limits the step";
  if (l.dt == 0)
    s << est.integrator << " has no stable step on " << l.state << " (its undamped " << l.mode << " mode, " << l.where
      << ")";
  else
    s << est.integrator << "'s limit " << l.dt << " s on " << l.state << " (" << l.mode << " mode, " << l.where << ")";
  return s.str();
}

namespace {
nlohmann::json number(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }
}  // namespace

nlohmann::json limit_json(const MechanicalLimit& l) {
  return {{"dt_limit", number(l.dt)},      {"binding_mode", l.mode},      {"binding_where", l.where},
          {"state", l.state},              {"omega_max", l.omega_max},    {"coordinates", l.coordinates},
          {"contacts", l.contacts},        {"blow_up_dt_limit", number(l.blow_up_dt)}};
}

MechanicalLimit limit_of_json(const nlohmann::json& j) {
  MechanicalLimit l;
  l.dt = j["dt_limit"].is_null() ? INFINITY : j["dt_limit"].get<double>();
  l.mode = j["binding_mode"].get<std::string>();
  l.where = j["binding_where"].get<std::string>();
  l.state = j["state"].get<std::string>();
  l.omega_max = j["omega_max"].get<double>();
  l.coordinates = j["coordinates"].get<int>();
  l.contacts = j["contacts"].get<int>();
  l.blow_up_dt = j["blow_up_dt_limit"].is_null() ? INFINITY : j["blow_up_dt_limit"].get<double>();
  return l;
}

nlohmann::json estimate_json(const StabilityEstimate& est) {
  nlohmann::json j = limit_json(est.limit);
  j["integrator"] = est.integrator;
  j["recommended_dt"] = number(est.recommended_dt);
  j["contact_duration"] = number(est.contact_duration);
  j["shortest_pair"] = est.shortest_pair;
  j["rayleigh_dt"] = number(est.rayleigh);
  j["estimate_seconds"] = est.seconds;
  if (std::isfinite(est.thermal_dt_limit_network) || std::isfinite(est.thermal_dt_limit)) {
    j["thermal_dt_limit"] = number(est.thermal_dt_limit);
    j["thermal_dt_limit_network"] = number(est.thermal_dt_limit_network);
    j["thermal_relaxation_time"] = number(est.thermal_relaxation_time);
    j["conduction_dt_limit"] = number(est.conduction_dt_limit);
  }
  return j;
}

DtVerdict judge_dt(const StabilityEstimate& est, double dt, const Scene& scene) {
  DtVerdict v;
  auto refused = [&v](const std::string& why) {
    v.unstable = true;
    v.warnings.push_back(why);
    return v;
  };
  // Named at t_end and dt, where the scene sets the run's length in steps, like every refusal of a
  // scene's value (dt alone changed on the command line was blamed on t_end's line).
  const std::string at = scene.t_end_at.file.empty() ? ""
                         : scene.dt_at.file.empty()  ? describe(scene.t_end_at) + ": "
                                                     : describe(scene.t_end_at) + " and " + describe(scene.dt_at) + ": ";
  if (scene.control.rtol == 0)
    if (auto why = too_many_moving_steps(scene, dt, scene.t_end)) return refused(at + *why);
  if (scene.freeze.enabled && scene.control.rtol == 0)
    if (auto why = too_many_steps("freeze.dt", scene.freeze.dt, scene.t_end))
      return refused(scene.t_end_at.file.empty() || scene.freeze.dt_at.file.empty()
                         ? at + *why
                         : describe(scene.t_end_at) + " and " + describe(scene.freeze.dt_at) + ": " + *why);
  if (not_a_number(est))
    return refused("the time-step estimates are not numbers: the scene's masses, stiffnesses (and their tangential "
                   "and rolling ratios), conductivities, heat capacities or speeds overflow double precision (about "
                   "1.8e308)");
  if (scene.thermal) judge_conduction(est, dt, scene, v);
  if (!v.unstable && !scene.frozen) judge_mechanics(est, dt, scene, v);
  return v;
}

}  // namespace kiln
