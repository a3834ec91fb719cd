#include "src/dem_system.h"

#include <algorithm>
#include <cmath>

#include "contact/normal_force.h"
#include "contact/tangential_force.h"
#include "src/wall_geometry.h"

namespace kiln {

double disc_mass(const Scene& scene, double r, double density) {
  return scene.mass_model == MassModel::sphere ? 4.0 / 3.0 * M_PI * r * r * r * density
                                               : M_PI * r * r * scene.thickness * density;
}

double disc_inertia(const Scene& scene, double m, double r) {
  return (scene.mass_model == MassModel::sphere ? 0.4 : 0.5) * m * r * r;
}

namespace {

double automatic_skin(const Scene& scene) {
  double sum = 0;
  for (double r : scene.radius) sum += 2 * r;
  return scene.radius.empty() ? 1e-3 : 0.2 * sum / scene.radius.size();
}

}  // namespace

DemSystem::DemSystem(const Scene& scene)
    : scene_(scene), n_(scene.n_particles()), broadphase_(scene.skin > 0 ? scene.skin : automatic_skin(scene)) {
  const int nm = scene.n_materials();
  flags_.resize(nm * nm);
  for (int a = 0; a < nm; ++a)
    for (int b = 0; b < nm; ++b) {
      const PairLaw& law = scene.law(a, b);
      LawFlags& f = flags_[a * nm + b];
      f.mu = law.friction;
      f.mu_roll = law.rolling_friction;
      f.hertz = law.model == NormalModel::hertz;
      f.tension = law.tension;
      f.tangential = law.friction > 0;
      f.rolling = law.rolling_friction > 0;
      f.kt_ratio = law.tangential_stiffness_ratio * (f.hertz ? 1.5 : 1.0);
      f.ct_ratio = law.tangential_damping_ratio;
      f.beta = law.damping_rate > 0 ? 0 : contact::restitution_damping(law.restitution, f.hertz, f.tension);
      const Material &ma = scene.materials[a], &mb = scene.materials[b];
      f.conduction = {law.conduction, ma.conductivity, mb.conductivity, law.conductance, law.modulus_ratio,
                      law.effective_modulus, scene.thickness, law.contact_resistance};
      if (ma.conductivity > 0 && mb.conductivity > 0)
        f.heat_share = thermal::heat_partition(ma.electrical_resistivity, mb.electrical_resistivity, ma.conductivity,
                                               mb.conductivity);
    }
  // A scene that uses friction or rolling resistance anywhere carries rotation; otherwise discs
  // cannot spin and no angles are integrated.
  for (int i = 0; i < n_ && !rotates_; ++i) {
    for (int b = 0; b < nm; ++b) {
      const LawFlags& f = flags_[scene.material[i] * nm + b];
      rotates_ = rotates_ || f.tangential || f.rolling;
      has_tangential_ = has_tangential_ || f.tangential;
    }
    rotates_ = rotates_ || scene.angular_velocity[i] != 0;
  }
  thermal_ = scene.thermal;
  events_ = scene.control.contact_events;
  layout_.nq = (rotates_ ? 3 : 2) * n_;
  layout_.nz = ledger_count() + (thermal_ ? n_ : 0);
  heat_power_factor_friction_ = scene.heat_from_dissipation != HeatFromDissipation::none;
  heat_power_factor_damping_ = scene.heat_from_dissipation == HeatFromDissipation::all;

  radius_ = scene.radius;
  for (double r : radius_) inv_radius_.push_back(1 / r);
  material_ = scene.material;
  for (int i = 0; i < n_; ++i) {
    const double m = disc_mass(scene, radius_[i], scene.materials[material_[i]].density);
    mass_.push_back(m);
    inv_mass_.push_back(1 / m);
    inertia_.push_back(disc_inertia(scene, m, radius_[i]));
    inv_inertia_.push_back(1 / inertia_.back());
    if (thermal_) {
      capacity_.push_back(m * scene.materials[material_[i]].specific_heat);
      inv_capacity_.push_back(1 / capacity_.back());
    }
  }
  for (const Wall& w : scene.walls) moving_walls_ = moving_walls_ || w.motion.kind != WallMotion::Kind::fixed;
  x_ref_.resize(n_);
  y_ref_.resize(n_);
  update_walls(0);
}

std::vector<double> DemSystem::initial_state() const {
  std::vector<double> y(layout_.size(), 0.0);
  for (int i = 0; i < n_; ++i) {
    y[x_at() + i] = scene_.position[i].x;
    y[y_at() + i] = scene_.position[i].y;
    y[vx_at() + i] = scene_.velocity[i].x;
    y[vy_at() + i] = scene_.velocity[i].y;
    if (rotates_) y[omega_at() + i] = scene_.angular_velocity[i];
    if (thermal_) y[temperature_at() + i] = scene_.temperature[i];
  }
  return y;
}

void DemSystem::wall_geometry(double t, std::vector<Vec2>& a, std::vector<Vec2>& b) const {
  a.resize(scene_.segments.size());
  b.resize(scene_.segments.size());
  for (size_t s = 0; s < scene_.segments.size(); ++s) {
    const Segment& seg = scene_.segments[s];
    const WallMotion& m = scene_.walls[seg.wall].motion;
    a[s] = wall_point_at(m, seg.a, t);
    b[s] = wall_point_at(m, seg.b, t);
  }
}

void DemSystem::update_walls(double t) {
  if (t == seg_time_) return;
  wall_geometry(t, seg_a_, seg_b_);
  seg_time_ = t;
}

void DemSystem::prepare(double t, const double* y, double lookahead) {
  if (!built_ || !covers(t, y, lookahead)) rebuild(t, y);
}

bool DemSystem::neighbours_cover(double t, const double* y) const { return built_ && covers(t, y, 0); }

// Verlet-list criterion: no pair can have closed a gap of one skin since the last rebuild if
// every particle moved less than half a skin (and a particle plus its wall less than a skin).
// Within a multi-stage step positions may wander ahead by about lookahead * |v|: counted twice.
bool DemSystem::covers(double t, const double* y, double lookahead) const {
  const double* px = y + x_at();
  const double* py = y + y_at();
  const double* vx = y + vx_at();
  const double* vy = y + vy_at();
  double d2max = 0, v2max = 0;
  for (int i = 0; i < n_; ++i) {
    const double dx = px[i] - x_ref_[i], dy = py[i] - y_ref_[i];
    d2max = std::max(d2max, dx * dx + dy * dy);
    v2max = std::max(v2max, vx[i] * vx[i] + vy[i] * vy[i]);
  }
  const double moved = std::sqrt(d2max) + 2 * lookahead * std::sqrt(v2max);
  double wall_moved = 0;
  for (size_t w = 0; w < scene_.walls.size(); ++w)
    wall_moved = std::max(wall_moved, wall_max_displacement(scene_.walls[w].motion, scene_.segments,
                                                            static_cast<int>(w), t_ref_, t + lookahead));
  const double skin = broadphase_.skin();
  return 2 * moved < skin && moved + wall_moved < skin;
}

void DemSystem::rebuild(double t, const double* y) {
  const double* px = y + x_at();
  const double* py = y + y_at();
  broadphase_.particle_pairs(px, py, radius_.data(), n_, candidates_);
  pp_.replace(candidates_);
  set_coefficients(pp_, false);
  update_walls(t);
  broadphase_.wall_pairs(px, py, radius_.data(), n_, seg_a_, seg_b_, candidates_);
  pw_.replace(candidates_);
  set_coefficients(pw_, true);
  if (events_) lock_contacts(t, y, nullptr);
  std::copy_n(px, n_, x_ref_.data());
  std::copy_n(py, n_, y_ref_.data());
  t_ref_ = t;
  built_ = true;
  ++rebuilds_;
}

void DemSystem::set_coefficients(ContactList& list, bool walls) {
  const int nm = scene_.n_materials();
  for (int p = 0; p < list.size(); ++p) {
    const int i = list.i[p], j = list.j[p];
    const int mi = material_[i];
    const int mj = walls ? scene_.walls[scene_.segments[j].wall].material : material_[j];
    const PairLaw& law = scene_.law(mi, mj);
    const LawFlags& f = flags_[mi * nm + mj];
    // A wall is a flat body of infinite mass: m_eff = m_i and R* = r_i.
    const double m_eff = walls ? mass_[i] : mass_[i] * mass_[j] / (mass_[i] + mass_[j]);
    const double r_eff = walls ? radius_[i] : radius_[i] * radius_[j] / (radius_[i] + radius_[j]);
    const double k = f.hertz ? 4.0 / 3.0 * law.effective_modulus * std::sqrt(r_eff) : law.stiffness;
    const double c = law.damping_rate > 0 ? m_eff * law.damping_rate : f.beta * std::sqrt(m_eff * k);
    list.law[p] = static_cast<uint16_t>(mi * nm + mj);
    list.k[p] = k;
    list.c[p] = c;
  }
}

void DemSystem::accept(double t) {
  pp_.commit();
  pw_.commit();
  t_committed_ = t;
}

namespace {

// Everything the force loops read, gathered once per evaluation.
struct Fields {
  const double *x, *y, *vx, *vy, *w;
  double *fx, *fy, *torque;
};

// Forces of one contact with normal n (from i towards the other body), overlap > 0, relative
// velocity `vrel` of i's surface against the other's at the contact. Returns the normal force
// and writes the tangential force along t = perp(n) and the new elongation.
struct ContactForce {
  double normal = 0, tangential = 0;
  double damping_power = 0, friction_power = 0;  // dissipated (W)
};

inline ContactForce contact_force(const contact::NormalLaw& nl, double overlap, double vn, double vt, double kt,
                                  double ct, double mu, bool tangential, double spring, double dt_hist,
                                  double inv_dt_hist, double& trial) {
  ContactForce f;
  f.normal = contact::normal_force(nl, overlap, vn);
  f.damping_power = contact::normal_dissipation(nl, overlap, vn, f.normal);
  if (tangential) {
    const double scale = nl.hertz ? std::sqrt(std::fmax(overlap, 0.0)) : 1.0;
    const double cscale = nl.hertz ? std::sqrt(scale) : 1.0;
    const auto t = contact::tangential_force({kt * scale, ct * cscale, mu}, spring, vt, dt_hist, inv_dt_hist, f.normal);
    f.tangential = t.force;
    f.friction_power = t.dissipation;
    trial = t.spring;
  }
  return f;
}

}  // namespace

// A pair that is not touching has no tangential spring; an elongation it still had is released
// (its energy counted as dissipated). Hertz springs have vanished with the overlap already.
double DemSystem::release(ContactList& list, int p, double dt_hist) const {
  list.trial[p] = 0;
  const LawFlags& lf = flags_[list.law[p]];
  if (!lf.tangential || lf.hertz || list.spring[p] == 0) return 0;
  return contact::release_dissipation({lf.kt_ratio * list.k[p], 0, 0}, list.spring[p], dt_hist);
}

void DemSystem::evaluate(double t, const double* y, double* ydot, Part part, const double* temps) {
  const int nq = layout_.nq;
  if (part == Part::implicit_only || part == Part::jacobian) {
    // IMEX: conduction alone is implicit (linear in the temperatures `temps`); the walls' heat
    // sources enter the implicit part, not its Jacobian.
    std::fill_n(ydot, layout_.size(), 0.0);
    if (moving_walls_) update_walls(t);
    double* heat = ydot + temperature_at();
    const double heat_walls = conduct(t, y, temps ? temps : y + temperature_at(), heat, part == Part::implicit_only);
    for (int i = 0; i < n_; ++i) heat[i] *= inv_capacity_[i];
    if (part == Part::implicit_only) ydot[ledger_at() + ledger_heat_walls] = heat_walls;
    return;
  }
  std::copy_n(y + nq, nq, ydot);  // dq/dt = v
  Fields s{y + x_at(), y + y_at(), y + vx_at(), y + vy_at(), rotates_ ? y + omega_at() : nullptr,
           ydot + vx_at(), ydot + vy_at(), rotates_ ? ydot + omega_at() : nullptr};
  std::fill_n(ydot + nq, nq, 0.0);
  if (moving_walls_) update_walls(t);
  const double dt_hist = t - t_committed_;
  const double inv_dt_hist = dt_hist > 0 ? 1 / dt_hist : 0.0;
  double damping = 0, friction = 0, walls_work = 0, worst = 0;
  // Heat (thermal scenes only): dissipation turned to heat here; conduction, the implicit part
  // under IMEX, after the contact loops.
  double* heat = thermal_ ? ydot + temperature_at() : nullptr;
  if (thermal_) std::fill_n(heat, n_, 0.0);
  double heat_generated = 0;

  // Particle-particle contacts.
  for (int p = 0, np = pp_.size(); p < np; ++p) {
    const int i = pp_.i[p], j = pp_.j[p];
    const double dx = s.x[j] - s.x[i], dy = s.y[j] - s.y[i];
    const double rsum = radius_[i] + radius_[j];
    const double d2 = dx * dx + dy * dy;
    // With contact events the acting set is locked for the step: an acting contact keeps its
    // (continued) law past separation until its release is located, a new one waits for its onset.
    if (events_ ? !pp_.active[p] : d2 >= rsum * rsum) {
      friction += release(pp_, p, dt_hist);
      continue;
    }
    const double d = std::sqrt(d2);
    const double inv_d = 1 / d;
    const double nx = dx * inv_d, ny = dy * inv_d;  // from i to j
    const double overlap = rsum - d;
    const LawFlags& lf = flags_[pp_.law[p]];
    double rvx = s.vx[i] - s.vx[j], rvy = s.vy[i] - s.vy[j];
    if (s.w) {  // surface velocity from spin: (w_i r_i + w_j r_j) perp(n)
      const double spin = s.w[i] * radius_[i] + s.w[j] * radius_[j];
      rvx -= spin * ny;
      rvy += spin * nx;
    }
    const double vn = rvx * nx + rvy * ny;   // approach speed
    const double vt = -rvx * ny + rvy * nx;  // slip along t = perp(n)
    const ContactForce f = contact_force({pp_.k[p], pp_.c[p], lf.hertz, lf.tension}, overlap, vn, vt,
                                         lf.kt_ratio * pp_.k[p], lf.ct_ratio * pp_.c[p], lf.mu, lf.tangential, pp_.spring[p], dt_hist, inv_dt_hist, pp_.trial[p]);
    const double fx = -f.normal * nx - f.tangential * ny;
    const double fy = -f.normal * ny + f.tangential * nx;
    s.fx[i] += fx;
    s.fy[i] += fy;
    s.fx[j] -= fx;
    s.fy[j] -= fy;
    damping += f.damping_power;
    friction += f.friction_power;
    double rolling_power = 0;
    if (s.torque) {
      s.torque[i] += radius_[i] * f.tangential;
      s.torque[j] += radius_[j] * f.tangential;
      if (lf.rolling) {
        const double spin = s.w[i] - s.w[j];
        const double m = contact::rolling_torque(lf.mu_roll, radius_[i] * radius_[j] / rsum, f.normal, spin);
        s.torque[i] += m;
        s.torque[j] -= m;
        rolling_power = -m * spin;
        friction += rolling_power;
      }
    }
    if (heat) {
      // The dissipation that becomes heat, shared by beta (Nguyen et al. 2009:
      // m c_p dT/dt = sum_j (H (T_j - T_i) + E_f / (2 dt))); conduction is added by conduct().
      const double generated = heat_power_factor_friction_ * (f.friction_power + rolling_power) +
                               heat_power_factor_damping_ * f.damping_power;
      heat[i] += lf.heat_share * generated;
      heat[j] += (1 - lf.heat_share) * generated;
      heat_generated += generated;
    }
    worst = std::max(worst, overlap * std::max(inv_radius_[i], inv_radius_[j]));
  }

  // Particle-wall contacts. A wall point's velocity enters the relative velocity; the work the
  // wall does on the particle is F . u_wall.
  for (int p = 0, np = pw_.size(); p < np; ++p) {
    const int i = pw_.i[p], sgi = pw_.j[p];
    const double r = radius_[i];
    WallHit hit;
    if ((events_ && !pw_.active[p]) ||
        !disc_segment_contact(scene_.segments, seg_a_, seg_b_, sgi, {s.x[i], s.y[i]}, r, hit, events_)) {
      friction += release(pw_, p, dt_hist);
      continue;
    }
    const Vec2 n = hit.normal;
    const double overlap = hit.overlap;
    const Vec2 closest = hit.closest;
    const int wall = scene_.segments[sgi].wall;
    const Vec2 u = wall_velocity_at(scene_.walls[wall].motion, closest, t);
    const LawFlags& lf = flags_[pw_.law[p]];
    double rvx = s.vx[i] - u.x, rvy = s.vy[i] - u.y;
    if (s.w) {
      rvx -= s.w[i] * r * n.y;
      rvy += s.w[i] * r * n.x;
    }
    const double vn = rvx * n.x + rvy * n.y;
    const double vt = -rvx * n.y + rvy * n.x;
    const ContactForce f = contact_force({pw_.k[p], pw_.c[p], lf.hertz, lf.tension}, overlap, vn, vt,
                                         lf.kt_ratio * pw_.k[p], lf.ct_ratio * pw_.c[p], lf.mu, lf.tangential, pw_.spring[p], dt_hist, inv_dt_hist, pw_.trial[p]);
    const double fx = -f.normal * n.x - f.tangential * n.y;
    const double fy = -f.normal * n.y + f.tangential * n.x;
    s.fx[i] += fx;
    s.fy[i] += fy;
    damping += f.damping_power;
    friction += f.friction_power;
    walls_work += fx * u.x + fy * u.y;
    double rolling_power = 0;
    if (s.torque) {
      s.torque[i] += r * f.tangential;
      if (lf.rolling) {
        const WallMotion& m = scene_.walls[wall].motion;
        const double wall_spin = m.kind == WallMotion::Kind::rotate ? m.omega : 0.0;
        const double spin = s.w[i] - wall_spin;
        const double mr = contact::rolling_torque(lf.mu_roll, r, f.normal, spin);
        s.torque[i] += mr;
        rolling_power = -mr * spin;
        friction += rolling_power;
        walls_work += mr * wall_spin;
      }
    }
    if (heat) {  // the wall keeps its share of frictional heat
      const double generated = lf.heat_share * (heat_power_factor_friction_ * (f.friction_power + rolling_power) +
                                                heat_power_factor_damping_ * f.damping_power);
      heat[i] += generated;
      heat_generated += generated;
    }
    worst = std::max(worst, overlap * inv_radius_[i]);
  }

  const double heat_walls = heat && part == Part::all ? conduct(t, y, y + temperature_at(), heat, true) : 0.0;

  const double gx = scene_.gravity.x, gy = scene_.gravity.y;
  for (int i = 0; i < n_; ++i) {
    s.fx[i] = s.fx[i] * inv_mass_[i] + gx;
    s.fy[i] = s.fy[i] * inv_mass_[i] + gy;
  }
  if (s.torque)
    for (int i = 0; i < n_; ++i) s.torque[i] *= inv_inertia_[i];
  double* ledger = ydot + ledger_at();
  ledger[ledger_damping] = damping;
  ledger[ledger_friction] = friction;
  ledger[ledger_walls] = walls_work;
  if (heat) {
    for (int i = 0; i < n_; ++i) heat[i] *= inv_capacity_[i];
    ledger[ledger_heat_walls] = heat_walls;
    ledger[ledger_heat_generated] = heat_generated;
  }
  max_overlap_fraction_ = worst;
}

// Conductance of candidate pair p, 0 unless its discs touch (and, with contact events, it acts).
// Hertz conductance takes the elastic normal force: the contact radius is set by the elastic
// deformation, the dashpot does not widen it.
double DemSystem::pair_conductance(const double* px, const double* py, int p) const {
  if (events_ && !pp_.active[p]) return 0;
  const int i = pp_.i[p], j = pp_.j[p];
  const double dx = px[j] - px[i], dy = py[j] - py[i], rsum = radius_[i] + radius_[j];
  const double d2 = dx * dx + dy * dy;
  if (d2 >= rsum * rsum) return 0;
  const double d = std::sqrt(d2), overlap = rsum - d;
  const LawFlags& lf = flags_[pp_.law[p]];
  const double fn = contact::normal_force({pp_.k[p], pp_.c[p], lf.hertz, lf.tension}, overlap, 0.0);
  return thermal::conductance(lf.conduction, radius_[i], radius_[j], d, fn);
}

// Conductance between particle pw.i[p] and its wall segment (walls at their geometry a, b), 0
// unless they touch; `wall` is set to the wall's index.
double DemSystem::wall_conductance(const double* px, const double* py, const std::vector<Vec2>& a,
                                   const std::vector<Vec2>& b, int p, int& wall) const {
  const int i = pw_.i[p];
  wall = scene_.segments[pw_.j[p]].wall;
  WallHit hit;
  if ((events_ && !pw_.active[p]) || !scene_.walls[wall].temperature.isothermal() ||
      !disc_segment_contact(scene_.segments, a, b, pw_.j[p], {px[i], py[i]}, radius_[i], hit, events_))
    return 0;
  const LawFlags& lf = flags_[pw_.law[p]];
  const double fn = contact::normal_force({pw_.k[p], pw_.c[p], lf.hertz, lf.tension}, hit.overlap, 0.0);
  return thermal::conductance(lf.conduction, radius_[i], INFINITY, radius_[i] - hit.overlap, fn);
}

// Conduction ([thesis] eq. II.6-II.8): heat[i] += sum_j H_ij (T_j - T_i) + sum_w H_iw (T_w - T_i)
// over isothermal walls, whose temperatures are taken as 0 without `wall_sources` (the Jacobian).
// Returns the heat the walls give (W). Wall geometry must be current (update_walls).
double DemSystem::conduct(double t, const double* y, const double* temp, double* heat, bool wall_sources) const {
  const double *px = y + x_at(), *py = y + y_at();
  for (int p = 0, np = pp_.size(); p < np; ++p) {
    const int i = pp_.i[p], j = pp_.j[p];
    const double q = pair_conductance(px, py, p) * (temp[j] - temp[i]);
    heat[i] += q;
    heat[j] -= q;
  }
  double heat_walls = 0;
  for (int p = 0, np = pw_.size(); p < np; ++p) {
    int wall = 0;
    const double h = wall_conductance(px, py, seg_a_, seg_b_, p, wall);
    if (h == 0) continue;
    const double q = h * ((wall_sources ? scene_.walls[wall].temperature.at(t) : 0.0) - temp[pw_.i[p]]);
    heat[pw_.i[p]] += q;
    heat_walls += q;
  }
  return heat_walls;
}

EnergyLedger DemSystem::energy(double t, const double* y) const {
  EnergyLedger e;
  const double *px = y + x_at(), *py = y + y_at(), *vx = y + vx_at(), *vy = y + vy_at();
  for (int i = 0; i < n_; ++i) {
    e.kinetic += 0.5 * mass_[i] * (vx[i] * vx[i] + vy[i] * vy[i]);
    if (rotates_) e.kinetic += 0.5 * inertia_[i] * y[omega_at() + i] * y[omega_at() + i];
    e.potential -= mass_[i] * (scene_.gravity.x * px[i] + scene_.gravity.y * py[i]);
  }
  std::vector<Vec2> a, b;
  wall_geometry(t, a, b);
  double normal_elastic = 0, tangential_elastic = 0;
  auto add = [&](const ContactList& list, int p, double overlap) {
    const LawFlags& lf = flags_[list.law[p]];
    normal_elastic += contact::normal_elastic_energy({list.k[p], list.c[p], lf.hertz, lf.tension}, overlap);
    if (lf.tangential) {
      const double kt = lf.kt_ratio * list.k[p] * (lf.hertz ? std::sqrt(overlap) : 1.0);
      tangential_elastic += contact::tangential_elastic_energy({kt, 0, 0}, list.spring[p]);
    }
  };
  for (int p = 0; p < pp_.size(); ++p) {
    const int i = pp_.i[p], j = pp_.j[p];
    const double overlap = radius_[i] + radius_[j] - std::hypot(px[j] - px[i], py[j] - py[i]);
    if (overlap > 0) add(pp_, p, overlap);
  }
  for (int p = 0; p < pw_.size(); ++p) {
    const int i = pw_.i[p];
    WallHit hit;
    if (disc_segment_contact(scene_.segments, a, b, pw_.j[p], {px[i], py[i]}, radius_[i], hit))
      add(pw_, p, hit.overlap);
  }
  const double* ledger = y + ledger_at();
  e.elastic = normal_elastic + tangential_elastic;
  e.dissipated_damping = ledger[ledger_damping];
  e.dissipated_friction = ledger[ledger_friction];
  e.work_by_walls = ledger[ledger_walls];
  if (thermal_) {
    for (int i = 0; i < n_; ++i) e.thermal += capacity_[i] * y[temperature_at() + i];
    e.heat_from_walls = ledger[ledger_heat_walls];
    e.heat_from_dissipation = ledger[ledger_heat_generated];
  }
  return e;
}

double DemSystem::pair_overlap(const double* px, const double* py, int p) const {
  const int i = pp_.i[p], j = pp_.j[p];
  return radius_[i] + radius_[j] - std::hypot(px[j] - px[i], py[j] - py[i]);
}

double DemSystem::wall_overlap(const double* px, const double* py, const std::vector<Vec2>& a,
                               const std::vector<Vec2>& b, int p) const {
  const int i = pw_.i[p];
  WallHit hit;
  // A vertex owned by the neighbouring segment is no contact of this one: always apart.
  return disc_segment_contact(scene_.segments, a, b, pw_.j[p], {px[i], py[i]}, radius_[i], hit, true) ? hit.overlap
                                                                                                     : -radius_[i];
}

void DemSystem::event_functions(double t, const double* y, double* g) const {
  const double *px = y + x_at(), *py = y + y_at();
  std::vector<Vec2>&a = event_a_, &b = event_b_;  // kept: event location runs every step
  wall_geometry(t, a, b);
  for (int p = 0; p < pp_.size(); ++p) g[p] = pair_overlap(px, py, p);
  for (int p = 0; p < pw_.size(); ++p) g[pp_.size() + p] = wall_overlap(px, py, a, b, p);
}

void DemSystem::lock_contacts(double t, const double* y, const int* flips) {
  // After a located event the root finder's directions decide (the overlap there is ~0);
  // contacts not known yet (the start, new candidates) act where their overlap is positive.
  const double *px = y + x_at(), *py = y + y_at();
  std::vector<Vec2>&a = event_a_, &b = event_b_;  // kept: event location runs every step
  wall_geometry(t, a, b);
  for (int p = 0; p < pp_.size(); ++p) {
    if (flips && flips[p]) pp_.active[p] = flips[p] > 0;
    if (pp_.active[p] == 2) pp_.active[p] = pair_overlap(px, py, p) > 0;
  }
  for (int p = 0; p < pw_.size(); ++p) {
    const int k = pp_.size() + p;
    if (flips && flips[k]) pw_.active[p] = flips[k] > 0;
    if (pw_.active[p] == 2) pw_.active[p] = wall_overlap(px, py, a, b, p) > 0;
  }
}

std::vector<double> DemSystem::absolute_tolerances(const StepControl& c) const {
  std::vector<double> atol(layout_.size(), c.atol);
  auto fill = [&](int from, int count, double value) {
    if (from >= 0 && std::isfinite(value)) std::fill_n(atol.begin() + from, count, value);
  };
  fill(x_at(), 2 * n_, c.atol_position);
  fill(angle_at(), n_, c.atol_angle);
  fill(vx_at(), 2 * n_, c.atol_velocity);
  fill(omega_at(), n_, c.atol_velocity);
  fill(temperature_at(), n_, c.atol_temperature);
  return atol;
}

std::vector<ConductanceLink> DemSystem::conduction_links(double t, const double* y) const {
  std::vector<ConductanceLink> links;
  const double *px = y + x_at(), *py = y + y_at();
  for (int p = 0; p < pp_.size(); ++p)
    if (const double h = pair_conductance(px, py, p); h > 0) links.push_back({pp_.i[p], pp_.j[p], h});
  std::vector<Vec2> a, b;
  wall_geometry(t, a, b);
  for (int p = 0; p < pw_.size(); ++p) {
    int wall = 0;
    if (const double h = wall_conductance(px, py, a, b, p, wall); h > 0) links.push_back({pw_.i[p], -1 - wall, h});
  }
  return links;
}

DemSystem::ContactCount DemSystem::count_contacts(double t, const double* y) const {
  ContactCount count;
  const double *px = y + x_at(), *py = y + y_at();
  for (int p = 0; p < pp_.size(); ++p) {
    const int i = pp_.i[p], j = pp_.j[p];
    const double rs = radius_[i] + radius_[j];
    const double dx = px[j] - px[i], dy = py[j] - py[i];
    count.particle_particle += dx * dx + dy * dy < rs * rs;
  }
  std::vector<Vec2> a, b;
  wall_geometry(t, a, b);
  WallHit hit;
  for (int p = 0; p < pw_.size(); ++p) {
    const int i = pw_.i[p];
    count.particle_wall += disc_segment_contact(scene_.segments, a, b, pw_.j[p], {px[i], py[i]}, radius_[i], hit);
  }
  return count;
}

}  // namespace kiln
