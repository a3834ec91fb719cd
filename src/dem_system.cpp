#include "src/dem_system.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "contact/normal_force.h"
#include "contact/tangential_force.h"
#include "src/error.h"
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
    : scene_(scene),
      n_(scene.n_particles()),
      base_skin_(scene.skin > 0 ? scene.skin : automatic_skin(scene)),
      broadphase_(base_skin_) {
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
      f.kt_ratio = law.tangential_stiffness_ratio;
      f.ct_ratio = law.tangential_damping_ratio;
      f.rolling_model = law.rolling_model;
      f.eta_roll = law.rolling_damping_ratio;
      f.beta = law.damping_rate > 0 ? 0 : contact::restitution_damping(law.restitution, f.hertz, f.tension);
      const Material &ma = scene.materials[a], &mb = scene.materials[b];
      f.conduction = {law.conduction, ma.conductivity, mb.conductivity, law.conductance, law.modulus_ratio,
                      law.effective_modulus, scene.thickness, law.contact_resistance};
      if (ma.conductivity > 0 && mb.conductivity > 0)
        f.heat_share = thermal::heat_partition(ma.electrical_resistivity, mb.electrical_resistivity, ma.conductivity,
                                               mb.conductivity);
    }
  // A scene that uses friction or rolling resistance anywhere carries rotation and contact
  // history; otherwise discs cannot spin and no angles are integrated.
  std::vector<bool> used(nm, false);
  for (int i = 0; i < n_; ++i) {
    used[scene.material[i]] = true;
    rotates_ = rotates_ || scene.angular_velocity[i] != 0;
  }
  bool history = false;
  for (int a = 0; a < nm; ++a)
    for (int b = 0; b < nm && used[a]; ++b) history = history || flags_[a * nm + b].tangential || flags_[a * nm + b].rolling;
  rotates_ = rotates_ || history;
  pp_.history = pw_.history = history;
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
  wall_loads_.resize(scene.walls.size());
  update_walls(0, nullptr);
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

void DemSystem::wall_geometry(double t, const double*, std::vector<Vec2>& a, std::vector<Vec2>& b) const {
  a.resize(scene_.segments.size());
  b.resize(scene_.segments.size());
  for (size_t s = 0; s < scene_.segments.size(); ++s) {
    const Segment& seg = scene_.segments[s];
    const WallMotion& m = scene_.walls[seg.wall].motion;
    a[s] = wall_point_at(m, seg.a, t);
    b[s] = wall_point_at(m, seg.b, t);
  }
}

void DemSystem::update_walls(double t, const double* y) {
  if (t == seg_time_) return;
  wall_geometry(t, y, seg_a_, seg_b_);
  seg_time_ = t;
}

void DemSystem::prepare(double t, const double* y, double lookahead) {
  // A step that carries particles further than the base skin allows gets a wider skin for its
  // lists: covers() wants 2 (2 lookahead v) < skin; half as much again for the accelerations.
  if (!built_ || !covers(t, y, lookahead)) rebuild(t, y, 6 * lookahead * fastest_speed(y));
}

double DemSystem::fastest_speed(const double* y) const {
  double v2max = 0;
  for (int i = 0; i < n_; ++i) v2max = std::max(v2max, y[vx_at() + i] * y[vx_at() + i] + y[vy_at() + i] * y[vy_at() + i]);
  return std::sqrt(v2max);
}

// Lists at the step's start that cover where the step went: the skin three times the longest
// displacement, so that the check (twice the displacement below the skin) holds with a margin.
void DemSystem::rebuild_neighbours(double t, const double* y, double t_reached, const double* reached) {
  double travel = 0;
  for (int i = 0; i < n_; ++i)
    travel = std::max(travel, std::hypot(reached[x_at() + i] - y[x_at() + i], reached[y_at() + i] - y[y_at() + i]));
  double wall_travel = 0;
  for (size_t w = 0; w < scene_.walls.size(); ++w)
    wall_travel = std::max(wall_travel, wall_max_displacement(scene_.walls[w].motion, scene_.segments,
                                                              static_cast<int>(w), t, t_reached));
  rebuild(t, y, std::max(3 * travel, 1.5 * (travel + wall_travel)));
}

// At its current speeds no particle moves more than an eighth of the base skin in the step, so
// that prepare() keeps the base skin and no stage can pass a contact the lists do not hold.
double DemSystem::neighbour_step_bound(const double* y) const {
  const double v = fastest_speed(y);
  return v > 0 ? base_skin_ / (8 * v) : INFINITY;
}

std::string DemSystem::describe_travel(const double* from, const double* to, double h) const {
  int worst = 0;
  double travel = -1;
  for (int i = 0; i < n_; ++i) {
    const double d = std::hypot(to[x_at() + i] - from[x_at() + i], to[y_at() + i] - from[y_at() + i]);
    if (d > travel) {
      travel = d;
      worst = i;
    }
  }
  const double speed = std::hypot(from[vx_at() + worst], from[vy_at() + worst]);
  std::ostringstream s;
  s << "a step of " << h << " s moved particle " << worst << " by " << travel << " m (speed " << speed
    << " m/s at the step's start: step x speed = " << h * speed << " m) against a neighbour skin of "
    << broadphase_.skin() << " m, of which a step may use half";
  return s.str();
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

void DemSystem::rebuild(double t, const double* y, double skin) {
  const double* px = y + x_at();
  const double* py = y + y_at();
  broadphase_.set_skin(std::max(base_skin_, skin));
  broadphase_.particle_pairs(px, py, radius_.data(), n_, candidates_);
  pp_.replace(candidates_);
  set_coefficients(pp_, false);
  update_walls(t, y);
  broadphase_.wall_pairs(px, py, radius_.data(), n_, seg_a_, seg_b_, candidates_);
  pw_.replace(candidates_);
  set_coefficients(pw_, true);
  if (events_) lock_contacts(t, y, nullptr);
  if (pp_.history) {
    if (!built_) {  // the run starts here
      committed_angle_.assign(y + angle_at(), y + angle_at() + n_);
      trial_angle_ = committed_angle_;
      committed_time_ = trial_time_ = t;
    }
    frame_new_contacts(t, y);
  }
  std::copy_n(px, n_, x_ref_.data());
  std::copy_n(py, n_, y_ref_.data());
  t_ref_ = t;
  built_ = true;
  ++rebuilds_;
}

// Contacts present at the start of a run (or touching when they enter the list) are measured
// from the state they are first seen in: their springs start there, unstretched.
void DemSystem::frame_new_contacts(double t, const double* y) {
  const double *px = y + x_at(), *py = y + y_at();
  for (int p = 0; p < pp_.size(); ++p) {
    if (pp_.frame[p].known()) continue;
    const int i = pp_.i[p], j = pp_.j[p];
    const double dx = px[j] - px[i], dy = py[j] - py[i], d = std::hypot(dx, dy);
    const double overlap = radius_[i] + radius_[j] - d;
    if (overlap <= 0) continue;
    pp_.frame[p] = pp_.trial_frame[p] = {dx / d, dy / d, 0.0, -d};
  }
  update_walls(t, y);
  for (int p = 0; p < pw_.size(); ++p) {
    if (pw_.frame[p].known()) continue;
    const int i = pw_.i[p], sgi = pw_.j[p];
    WallHit hit;
    const Vec2 centre{px[i], py[i]};
    if (!disc_segment_contact(scene_.segments, seg_a_, seg_b_, sgi, centre, radius_[i], hit)) continue;
    const Vec2 rho = centre - seg_a_[sgi];
    pw_.frame[p] = pw_.trial_frame[p] = {hit.normal.x, hit.normal.y, dot(rho, perp(hit.normal)), dot(rho, hit.normal)};
  }
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

void DemSystem::save(Snapshot& s) const {
  pp_.save(s, "system.pairs.");
  pw_.save(s, "system.walls.");
  s.put("system.reference_x", x_ref_);
  s.put("system.reference_y", y_ref_);
  s.put("system.times", {t_ref_, committed_time_, trial_time_, broadphase_.skin(), max_overlap_fraction_});
  s.put_integers("system.counts", std::vector<long>{built_ ? 1 : 0, rebuilds_});
  s.put("system.committed_angle", committed_angle_);
  s.put("system.trial_angle", trial_angle_);
  s.put("system.work_force", work_force_);
}

// The Box2D tree is not restored: the candidate pairs are kept as saved, and the next rebuild's
// pairs are those of an exact test in double precision on whatever the tree reports (a superset).
void DemSystem::restore(const Snapshot& s) {
  pp_.restore(s, "system.pairs.");
  pw_.restore(s, "system.walls.");
  x_ref_ = s.reals("system.reference_x");
  y_ref_ = s.reals("system.reference_y");
  const std::vector<double>& times = s.reals("system.times");
  t_ref_ = times.at(0);
  committed_time_ = times.at(1);
  trial_time_ = times.at(2);
  broadphase_.set_skin(times.at(3));
  max_overlap_fraction_ = times.at(4);
  const std::vector<long long>& counts = s.integers("system.counts");
  built_ = counts.at(0) != 0;
  rebuilds_ = counts.at(1);
  committed_angle_ = s.reals("system.committed_angle");
  trial_angle_ = s.reals("system.trial_angle");
  work_force_ = s.reals("system.work_force");
  if (static_cast<int>(x_ref_.size()) != n_ || pp_.k.size() != pp_.i.size() || pw_.k.size() != pw_.i.size())
    throw InputError("the checkpoint's contact lists do not fit this scene's " + std::to_string(n_) + " particles");
}

void DemSystem::accept(double) {
  pp_.commit();
  pw_.commit();
  committed_angle_.swap(trial_angle_);
  committed_time_ = trial_time_;
}

namespace {

// Everything the force loops read, gathered once per evaluation.
struct Fields {
  const double *x, *y, *angle, *vx, *vy, *w;
  double *fx, *fy, *torque;
};

// Linear(ised) normal stiffness: k, or dF/d(overlap) of the Hertz spring, 3/2 k delta^1/2. The
// tangential and rolling springs scale with it.
inline double linearised_stiffness(const contact::NormalLaw& nl, double overlap) {
  return nl.hertz ? 1.5 * nl.k * std::sqrt(std::fmax(overlap, 0.0)) : nl.k;
}

}  // namespace

void DemSystem::forget(ContactList& list, int p) {
  list.trial[p] = 0;
  list.trial_roll[p] = 0;
  list.trial_frame[p] = {};
}

DemSystem::PairMasses DemSystem::pair_masses(int i, int j) const {
  if (j < 0) return {mass_[i], inertia_[i] + mass_[i] * radius_[i] * radius_[i], radius_[i], inertia_[i]};
  const double ri = inertia_[i] + mass_[i] * radius_[i] * radius_[i];
  const double rj = inertia_[j] + mass_[j] * radius_[j] * radius_[j];
  return {mass_[i] * mass_[j] / (mass_[i] + mass_[j]), ri * rj / (ri + rj),
          radius_[i] * radius_[j] / (radius_[i] + radius_[j]), inertia_[i] * inertia_[j] / (inertia_[i] + inertia_[j])};
}

contact::TangentialLaw DemSystem::tangential_law(const LawFlags& lf, const contact::NormalLaw& nl,
                                                 double overlap) const {
  const double quarter = nl.hertz ? std::sqrt(std::sqrt(std::fmax(overlap, 0.0))) : 1.0;
  return {lf.kt_ratio * linearised_stiffness(nl, overlap), lf.ct_ratio * nl.c * quarter, lf.mu};
}

contact::RollingLaw DemSystem::rolling_law(const LawFlags& lf, const contact::NormalLaw& nl, double overlap,
                                           const PairMasses& pm, double normal) const {
  return contact::rolling_law(lf.rolling_model, lf.mu_roll, linearised_stiffness(nl, overlap), pm.r_eff, pm.inertia,
                              pm.spin_inertia, pm.m_eff, lf.eta_roll, normal);
}

// The tangential and rolling springs of one touching contact at this state: their trial values
// are the committed ones plus what the contact points moved since the committed frame.
inline DemSystem::Friction DemSystem::friction(ContactList& list, int p, const LawFlags& lf, const contact::NormalLaw& nl,
                                        const ContactState& c, double normal) const {
  Friction f;
  const contact::ContactFrame& from = list.frame[p];
  const bool known = from.known();  // a contact that began in this step starts unstretched
  if (lf.tangential) {
    const contact::TangentialLaw law = tangential_law(lf, nl, c.overlap);
    const double trial =
        known ? list.spring[p] + contact::tangential_displacement(from, c.frame, c.arm_then, c.arm, c.spun_i, c.spun_other)
              : 0.0;
    const contact::TangentialResult t = contact::tangential_force(law, trial, c.slip_speed, normal);
    list.trial[p] = t.spring;
    f.force = t.force;
    f.work_rate -= t.force * c.slip_speed;
  }
  if (lf.rolling) {
    const contact::RollingLaw law = rolling_law(lf, nl, c.overlap, pair_masses(c.i, c.j), normal);
    const double trial = known ? list.roll[p] + (c.spun_i - c.spun_other) : 0.0;
    const contact::RollingResult r = contact::rolling_torque(law, trial, c.relative_spin);
    list.trial_roll[p] = r.spring;
    f.torque = r.torque;
    f.work_rate -= r.torque * c.relative_spin;
  }
  // Field by field: a struct copy through the stack stalled store forwarding (15 % of a run).
  contact::ContactFrame& to = list.trial_frame[p];
  to.nx = c.frame.nx;
  to.ny = c.frame.ny;
  to.rho_t = c.frame.rho_t;
  to.rho_n = c.frame.rho_n;
  return f;
}

void DemSystem::evaluate(double t, const double* y, double* ydot, Part part, const double* temps) {
  const int nq = layout_.nq;
  if (part == Part::implicit_only || part == Part::jacobian) {
    // IMEX: conduction alone is implicit (linear in the temperatures `temps`); the walls' heat
    // sources enter the implicit part, not its Jacobian. The heat the walls deliver is linear in
    // the temperatures too: its ledger rate has a Jacobian row, -sum H_w v_i, which a scheme
    // that corrects its slopes with the Jacobian needs to keep the ledger closed.
    std::fill_n(ydot, layout_.size(), 0.0);
    if (moving_walls_) update_walls(t, y);
    double* heat = ydot + temperature_at();
    const double heat_walls = conduct(t, y, temps ? temps : y + temperature_at(), heat, part == Part::implicit_only);
    for (int i = 0; i < n_; ++i) heat[i] *= inv_capacity_[i];
    ydot[ledger_at() + ledger_heat_walls] = heat_walls;
    return;
  }
  std::copy_n(y + nq, nq, ydot);  // dq/dt = v
  Fields s{y + x_at(), y + y_at(), rotates_ ? y + angle_at() : nullptr, y + vx_at(), y + vy_at(),
           rotates_ ? y + omega_at() : nullptr, ydot + vx_at(), ydot + vy_at(), rotates_ ? ydot + omega_at() : nullptr};
  std::fill_n(ydot + nq, nq, 0.0);
  if (moving_walls_) update_walls(t, y);
  const bool history = pp_.history;
  // The damping and friction ledgers' generalized forces (work_components()).
  work_force_.assign(2 * nq, 0.0);
  double* gd = work_force_.data();
  double* g = gd + nq;
  if (history) {
    std::copy_n(s.angle, n_, trial_angle_.data());
    trial_time_ = t;
  }
  double damping = 0, friction_work = 0, walls_work = 0, worst = 0;
  // Heat (thermal scenes only): dissipation turned to heat here; conduction, the implicit part
  // under IMEX, after the contact loops.
  double* heat = thermal_ ? ydot + temperature_at() : nullptr;
  if (thermal_) std::fill_n(heat, n_, 0.0);
  double heat_generated = 0;
  // The dissipation that becomes heat, shared by beta (Nguyen et al. 2009, eq. 1:
  // m c_p dT/dt = sum_j (H (T_j - T_i) + E_f / (2 dt))); conduction is added by conduct().
  // Friction heat is booked as the work of friction on the relative motion: what a spring
  // holds for a while is heat-to-be, subtracted again in energy() (see the header).
  auto make_heat = [&](double work_rate, double damping_power, int i, int j, double share) {
    const double generated = heat_power_factor_friction_ * work_rate + heat_power_factor_damping_ * damping_power;
    heat[i] += share * generated;
    heat_generated += share * generated;
    if (j >= 0) {  // a wall keeps its share
      heat[j] += (1 - share) * generated;
      heat_generated += (1 - share) * generated;
    }
  };

  // Particle-particle contacts.
  for (int p = 0, np = pp_.size(); p < np; ++p) {
    const int i = pp_.i[p], j = pp_.j[p];
    const double dx = s.x[j] - s.x[i], dy = s.y[j] - s.y[i];
    const double rsum = radius_[i] + radius_[j];
    const double d2 = dx * dx + dy * dy;
    // With contact events the acting set is locked for the step: an acting contact keeps its
    // (continued) law past separation until its release is located, a new one waits for its onset.
    if (events_ ? !pp_.active[p] : d2 >= rsum * rsum) {
      if (history) forget(pp_, p);
      continue;
    }
    const double d = std::sqrt(d2);
    const double inv_d = 1 / d;
    const double nx = dx * inv_d, ny = dy * inv_d;  // from i to j
    const double overlap = rsum - d;
    const LawFlags& lf = flags_[pp_.law[p]];
    const double rvx = s.vx[i] - s.vx[j], rvy = s.vy[i] - s.vy[j];
    const double vn = rvx * nx + rvy * ny;          // approach speed
    const double drift = -rvx * ny + rvy * nx;      // the centres' relative velocity along t
    const contact::NormalLaw nl{pp_.k[p], pp_.c[p], lf.hertz, lf.tension};
    const double fn = contact::normal_force(nl, overlap, vn);
    const double damping_power = contact::normal_dissipation(nl, overlap, vn, fn);
    Friction fr;
    if (history && (lf.tangential || lf.rolling)) {
      const double arm_i = contact::pair_arm(radius_[i], overlap), arm_j = contact::pair_arm(radius_[j], overlap);
      const double arm_then = contact::pair_arm(radius_[i], rsum + pp_.frame[p].rho_n);
      const ContactState c{{nx, ny, 0.0, -d},
                           arm_i,
                           arm_then,
                           s.angle[i] - committed_angle_[i],
                           s.angle[j] - committed_angle_[j],
                           i,
                           j,
                           overlap,
                           vn,
                           drift + s.w[i] * arm_i + s.w[j] * arm_j,
                           s.w[i] - s.w[j]};
      fr = friction(pp_, p, lf, nl, c, fn);
      s.torque[i] += arm_i * fr.force + fr.torque;
      s.torque[j] += arm_j * fr.force - fr.torque;
      // work_rate = -F_t ((v_i - v_j) . t + arm_i w_i + arm_j w_j) - M (w_i - w_j)
      g[i] += fr.force * ny;
      g[n_ + i] -= fr.force * nx;
      g[j] -= fr.force * ny;
      g[n_ + j] += fr.force * nx;
      g[2 * n_ + i] -= arm_i * fr.force + fr.torque;
      g[2 * n_ + j] -= arm_j * fr.force - fr.torque;
    } else if (history) {
      forget(pp_, p);
    }
    const double fx = -fn * nx - fr.force * ny;
    const double fy = -fn * ny + fr.force * nx;
    s.fx[i] += fx;
    s.fy[i] += fy;
    s.fx[j] -= fx;
    s.fy[j] -= fy;
    const double dashpot = contact::dashpot_force(nl, overlap, fn);  // damping_power = dashpot vn
    gd[i] += dashpot * nx;
    gd[n_ + i] += dashpot * ny;
    gd[j] -= dashpot * nx;
    gd[n_ + j] -= dashpot * ny;
    damping += damping_power;
    friction_work += fr.work_rate;
    if (heat) make_heat(fr.work_rate, damping_power, i, j, lf.heat_share);
    worst = std::max(worst, overlap * std::max(inv_radius_[i], inv_radius_[j]));
  }

  // Particle-wall contacts. The contact point is at the disc's lever arm, its full radius: the
  // wall's velocity there enters the relative velocity, and the work the wall does on the
  // particle is F . u_wall (plus the rolling couple times the wall's spin).
  for (int p = 0, np = pw_.size(); p < np; ++p) {
    const int i = pw_.i[p], sgi = pw_.j[p];
    const double r = radius_[i];
    WallHit hit;
    const Vec2 centre{s.x[i], s.y[i]};
    if ((events_ && !pw_.active[p]) ||
        !disc_segment_contact(scene_.segments, seg_a_, seg_b_, sgi, centre, r, hit, events_)) {
      if (history) forget(pw_, p);
      continue;
    }
    const Vec2 n = hit.normal;
    const double overlap = hit.overlap;
    const WallMotion& motion = scene_.walls[scene_.segments[sgi].wall].motion;
    const Vec2 point = centre + r * n;
    const Vec2 u = wall_velocity_at(motion, point, t);
    const LawFlags& lf = flags_[pw_.law[p]];
    const double rvx = s.vx[i] - u.x, rvy = s.vy[i] - u.y;
    const double vn = rvx * n.x + rvy * n.y;
    const double drift = -rvx * n.y + rvy * n.x;
    const contact::NormalLaw nl{pw_.k[p], pw_.c[p], lf.hertz, lf.tension};
    const double fn = contact::normal_force(nl, overlap, vn);
    const double damping_power = contact::normal_dissipation(nl, overlap, vn, fn);
    const double wall_spin = motion.kind == WallMotion::Kind::rotate ? motion.omega : 0.0;
    Friction fr;
    if (history && (lf.tangential || lf.rolling)) {
      const Vec2 rho = centre - seg_a_[sgi];  // from a point fixed on the wall
      const ContactState c{{n.x, n.y, dot(rho, perp(n)), dot(rho, n)},
                           r,
                           r,
                           s.angle[i] - committed_angle_[i],
                           wall_spin * (t - committed_time_),
                           i,
                           -1,
                           overlap,
                           vn,
                           drift + s.w[i] * r,
                           s.w[i] - wall_spin};
      fr = friction(pw_, p, lf, nl, c, fn);
      s.torque[i] += r * fr.force + fr.torque;
      walls_work += fr.torque * wall_spin;
      // work_rate = -F_t ((v_i - u) . t + r w_i) - M (w_i - wall spin): the u and spin parts are no g
      g[i] += fr.force * n.y;
      g[n_ + i] -= fr.force * n.x;
      g[2 * n_ + i] -= r * fr.force + fr.torque;
    } else if (history) {
      forget(pw_, p);
    }
    const double fx = -fn * n.x - fr.force * n.y;
    const double fy = -fn * n.y + fr.force * n.x;
    s.fx[i] += fx;
    s.fy[i] += fy;
    const double dashpot = contact::dashpot_force(nl, overlap, fn);  // damping_power = dashpot (v_i - u) . n
    gd[i] += dashpot * n.x;
    gd[n_ + i] += dashpot * n.y;
    damping += damping_power;
    friction_work += fr.work_rate;
    walls_work += fx * u.x + fy * u.y;
    if (heat) make_heat(fr.work_rate, damping_power, i, -1, lf.heat_share);
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
  ledger[ledger_friction] = friction_work;
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
    // From the initial position (energy.h): x - x0 is exact while x is within a factor 2 of x0, so
    // a scene far from the origin loses no digits to m g x.
    e.potential -= mass_[i] * (scene_.gravity.x * (px[i] - scene_.position[i].x) +
                               scene_.gravity.y * (py[i] - scene_.position[i].y));
  }
  std::vector<Vec2> a, b;
  wall_geometry(t, y, a, b);
  // The springs of the contacts as committed at the last accepted step (energy is asked for at
  // step ends, where the committed history belongs to the state).
  // held: the particles' shares of what friction springs hold, booked in their temperatures
  // already (evaluate books friction heat as work).
  double normal_elastic = 0, friction_elastic = 0, held = 0;
  auto add = [&](const ContactList& list, int p, int j, double overlap) {
    const LawFlags& lf = flags_[list.law[p]];
    const contact::NormalLaw nl{list.k[p], list.c[p], lf.hertz, lf.tension};
    normal_elastic += contact::normal_elastic_energy(nl, overlap);
    if (!list.history) return;
    double stored = 0;
    if (lf.tangential) stored += contact::tangential_elastic_energy(tangential_law(lf, nl, overlap), list.spring[p]);
    if (lf.rolling)
      stored += contact::rolling_elastic_energy(rolling_law(lf, nl, overlap, pair_masses(list.i[p], j), 0.0), list.roll[p]);
    friction_elastic += stored;
    held += (j >= 0 ? 1.0 : lf.heat_share) * stored;
  };
  for (int p = 0; p < pp_.size(); ++p) {
    const int i = pp_.i[p], j = pp_.j[p];
    const double overlap = radius_[i] + radius_[j] - std::hypot(px[j] - px[i], py[j] - py[i]);
    if (overlap > 0) add(pp_, p, j, overlap);
  }
  for (int p = 0; p < pw_.size(); ++p) {
    const int i = pw_.i[p];
    WallHit hit;
    if (disc_segment_contact(scene_.segments, a, b, pw_.j[p], {px[i], py[i]}, radius_[i], hit))
      add(pw_, p, -1, hit.overlap);
  }
  const double* ledger = y + ledger_at();
  e.elastic = normal_elastic + friction_elastic;
  e.dissipated_damping = ledger[ledger_damping];
  // What friction and rolling resistance did on the relative motion, less what their springs hold.
  e.dissipated_friction = ledger[ledger_friction] - friction_elastic;
  e.work_by_walls = ledger[ledger_walls];
  if (thermal_) {
    held *= heat_power_factor_friction_;
    for (int i = 0; i < n_; ++i) e.thermal += capacity_[i] * (y[temperature_at() + i] - scene_.temperature[i]);
    e.thermal -= held;
    e.heat_from_walls = ledger[ledger_heat_walls];
    e.heat_from_dissipation = ledger[ledger_heat_generated] - held;
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
  wall_geometry(t, y, a, b);
  for (int p = 0; p < pp_.size(); ++p) g[p] = pair_overlap(px, py, p);
  for (int p = 0; p < pw_.size(); ++p) g[pp_.size() + p] = wall_overlap(px, py, a, b, p);
}

void DemSystem::lock_contacts(double t, const double* y, const int* flips) {
  // After a located event the root finder's directions decide (the overlap there is ~0);
  // contacts not known yet (the start, new candidates) act where their overlap is positive.
  const double *px = y + x_at(), *py = y + y_at();
  std::vector<Vec2>&a = event_a_, &b = event_b_;  // kept: event location runs every step
  wall_geometry(t, y, a, b);
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

// Conduction's Jacobian: W the heat capacities, S the Laplacian of the contact conductances at
// (t, y) with the wall conductances on its diagonal, and the heat-from-walls row -sum H_iw.
bool DemSystem::diffusion_jacobian(double t, const double* y, DiffusionJacobian& out) const {
  if (!thermal_) return false;
  const double *px = y + x_at(), *py = y + y_at();
  out.reset(temperature_at(), capacity_, ledger_at() + ledger_heat_walls);
  for (int p = 0, np = pp_.size(); p < np; ++p)
    if (const double h = pair_conductance(px, py, p); h != 0) out.add_link(pp_.i[p], pp_.j[p], h);
  wall_geometry(t, y, event_a_, event_b_);
  for (int p = 0, np = pw_.size(); p < np; ++p) {
    int wall = 0;
    if (const double h = wall_conductance(px, py, event_a_, event_b_, p, wall); h != 0) out.add_link(pw_.i[p], -1, h);
  }
  return true;
}

std::vector<ConductanceLink> DemSystem::conduction_links(double t, const double* y) const {
  std::vector<ConductanceLink> links;
  const double *px = y + x_at(), *py = y + y_at();
  for (int p = 0; p < pp_.size(); ++p)
    if (const double h = pair_conductance(px, py, p); h > 0) links.push_back({pp_.i[p], pp_.j[p], h});
  std::vector<Vec2> a, b;
  wall_geometry(t, y, a, b);
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
  wall_geometry(t, y, a, b);
  WallHit hit;
  for (int p = 0; p < pw_.size(); ++p) {
    const int i = pw_.i[p];
    count.particle_wall += disc_segment_contact(scene_.segments, a, b, pw_.j[p], {px[i], py[i]}, radius_[i], hit);
  }
  return count;
}

}  // namespace kiln
