#include "src/dem/dem_system.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "src/base/error.h"
#include "src/base/parallel.h"

namespace kiln {

namespace {

double automatic_skin(const Scene& scene) {
  double sum = 0;
  for (double r : scene.radius) sum += 2 * r;
  return scene.radius.empty() ? 1e-3 : 0.2 * sum / scene.radius.size();
}

// What a wall's torque is taken about: its centre of rotation, else the mean of its end points.
Vec2 wall_reference(const Scene& scene, int w) {
  if (const auto centre = scene.walls[w].motion.centre_of_rotation()) return *centre;
  Vec2 sum;
  int count = 0;
  for (const Segment& s : scene.segments)
    if (s.wall == w) {
      sum = sum + s.a + s.b;
      count += 2;
    }
  return count ? (1.0 / count) * sum : Vec2{};
}

}  // namespace

DemSystem::DemSystem(const Scene& scene)
    : scene_(scene),
      cell_(scene.periodic),
      n_(scene.n_particles()),
      base_skin_(scene.skin > 0 ? scene.skin : automatic_skin(scene)),
      broadphase_(base_skin_) {
  const int nm = scene.n_materials();
  for (int a = 0; a < nm; ++a)
    for (int b = 0; b < nm; ++b) laws_.push_back(contact_coefficients(scene, a, b));
  // A scene that uses friction or rolling resistance anywhere carries rotation and contact
  // history; otherwise discs cannot spin and no angles are integrated.
  std::vector<bool> used(nm, false);
  for (int i = 0; i < n_; ++i) {
    used[scene.material[i]] = true;
    rotates_ = rotates_ || scene.angular_velocity[i] != 0;
  }
  bool history = false, rolling = false, first = true, damped = false, without_tension = false;
  for (int a = 0; a < nm; ++a)
    for (int b = 0; b < nm && used[a]; ++b) {
      const ContactCoefficients& law = laws_[a * nm + b];
      history = history || law.tangential || law.rolling;
      friction_everywhere_ = (first || friction_everywhere_) && law.tangential && !law.rolling;
      rolling = rolling || law.rolling;
      damped = damped || law.beta > 0 || law.law.damping_rate > 0;
      without_tension = without_tension || !law.law.tension;
      mixed_models_ = mixed_models_ || (!first && law.law.model != pair_model_);
      pair_model_ = law.law.model;
      first = false;
    }
  rotates_ = rotates_ || history;
  friction_batches_ = friction_everywhere_;
  pp_.history = pw_.history = history;
  pp_.rolling = pw_.rolling = rolling;
  thermal_ = scene.thermal;
  events_ = scene.control.contact_events;
  pp_.located = pw_.located = events_ && history;  // stick and slip located with onsets and releases
  pp_.events = pw_.events = events_;
  // A dashpot's pull is cut where a law has no tension, and carries no cap where friction is
  // located: its start is then an event too (ContactList::active).
  pp_.load_events = pw_.load_events = events_ && damped && (without_tension || history);
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
  for (size_t w = 0; w < scene.walls.size(); ++w) {
    moving_walls_ = moving_walls_ || scene.walls[w].motion.moves();
    wall_reference_.push_back(wall_reference(scene, static_cast<int>(w)));
    const bool body = scene.walls[w].motion.free_along_load();
    body_of_wall_.push_back(body ? static_cast<int>(body_wall_.size()) : -1);
    if (body) body_wall_.push_back(static_cast<int>(w));
  }
  layout_.nq += bodies();
  body_ref_.assign(bodies(), 0.0);
  body_acceleration_.assign(bodies(), 0.0);
  for (int i = 0; i < n_ && !scene.attached.empty(); ++i)
    if (scene.attached[i] != Scene::free_particle) attached_list_.push_back(i);
  has_attached_ = !attached_list_.empty();
  works_ = bodies() || has_attached_ ? 3 : 2;
  // Entries no stage writes (the dashpots' torques, the bodies' coordinates) stay 0.
  work_force_.assign(works_ * layout_.nq, 0.0);
  x_ref_.resize(n_);
  y_ref_.resize(n_);
  slot_.resize(n_);
  std::iota(slot_.begin(), slot_.end(), 0);
  particle_at_ = slot_;
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
  // Attached particles start with their wall's motion.
  for (int i : attached_list_) {
    const int w = scene_.attached[i];
    const WallMotion m = w >= 0 ? scene_.walls[w].motion : WallMotion{};
    const Vec2 u = m.velocity_at(scene_.position[i], 0);
    y[vx_at() + i] = u.x;
    y[vy_at() + i] = u.y;
    if (rotates_) y[omega_at() + i] = m.spin();
  }
  return y;
}

Vec2 DemSystem::body_offset(int w, const double* y) const {
  const int k = body_of_wall_[w];
  if (k < 0 || !y) return {};
  return scene_.walls[w].motion.along_load(y[body_at() + k]);
}

Vec2 DemSystem::body_velocity(int w, const double* y) const {
  const int k = body_of_wall_[w];
  if (k < 0 || !y) return {};
  return scene_.walls[w].motion.along_load(y[body_speed_at() + k]);
}

void DemSystem::wall_geometry(double t, const double* y, std::vector<Vec2>& a, std::vector<Vec2>& b) const {
  a.resize(scene_.segments.size());
  b.resize(scene_.segments.size());
  for (size_t s = 0; s < scene_.segments.size(); ++s) {
    const Segment& seg = scene_.segments[s];
    const WallMotion& m = scene_.walls[seg.wall].motion;
    const Vec2 shift = body_offset(seg.wall, y);
    a[s] = m.point_at(seg.a, t) + shift;
    b[s] = m.point_at(seg.b, t) + shift;
  }
}

// Walls where they are at (t, y). Without wall bodies the geometry is a function of t alone and
// is kept while t does not change.
void DemSystem::update_walls(double t, const double* y) {
  if (t == seg_time_ && bodies() == 0) return;
  wall_geometry(t, y, seg_a_, seg_b_);
  wall_centre_.resize(scene_.walls.size());
  for (size_t w = 0; w < scene_.walls.size(); ++w)
    wall_centre_[w] = scene_.walls[w].motion.point_at(wall_reference_[w], t) + body_offset(static_cast<int>(w), y);
  seg_time_ = t;
}

// The Box2D tree is not restored: the candidate pairs are kept as saved, and the next rebuild's
// pairs are those of an exact test in double precision on whatever the tree reports (a superset).
void DemSystem::state(SnapshotFields& f) {
  SnapshotFields pairs = f.within("pairs."), walls = f.within("walls.");
  pp_.state(pairs);
  pw_.state(walls);
  const size_t n = n_;
  f.field("reference_x", x_ref_, {n});
  f.field("reference_y", y_ref_, {n});
  double skin = broadphase_.skin();
  f.reals("times", t_ref_, committed_time_, trial_time_, skin, max_overlap_fraction_);
  f.integers("counts", built_, rebuilds_, reorders_);
  f.field("committed_angle", committed_angle_, {0, n});
  f.field("trial_angle", trial_angle_, {0, n});
  f.field("work_force", work_force_, {work_force_.size()});  // as the scene sizes it
  heat_work_state(f);
  f.field("body_reference", body_ref_, {static_cast<size_t>(bodies())});
  f.field("particle_at_slot", particle_at_, {n});
  f.field("ranked_share", ranked_share_);
  if (f.saving()) return;
  broadphase_.set_skin(skin);
  for (const ContactList* list : {&pp_, &pw_})
    for (uint16_t law : list->law)
      if (law >= laws_.size())
        throw InputError("the checkpoint's contacts name a material pair this scene does not have");
  auto within = [](const std::vector<int>& v, int count) { return std::all_of(v.begin(), v.end(), [count](int k) { return k >= 0 && k < count; }); };
  if (!within(pp_.i, n_) || !within(pp_.j, n_) || !within(pw_.i, n_) ||
      !within(pw_.j, static_cast<int>(scene_.segments.size())))
    throw InputError("the checkpoint's contacts name particles or wall segments this scene does not have");
  // A particle in contact with itself was resumed and stopped by the overlap check, blaming dt.
  for (size_t p = 0; p < pp_.i.size(); ++p)
    if (pp_.i[p] == pp_.j[p])
      throw InputError("the checkpoint's particle contacts (pairs.i, pairs.j) pair particle " + std::to_string(pp_.i[p]) +
                       " with itself (contact " + std::to_string(p) + ")");
  std::vector<int> order = particle_at_;
  std::sort(order.begin(), order.end());
  bool permutation = static_cast<int>(order.size()) == n_;
  for (int s = 0; permutation && s < n_; ++s) permutation = order[s] == s;
  if (!permutation)
    throw InputError("the checkpoint's particle order is not an order of this scene's " + std::to_string(n_) + " particles");
  for (int s = 0; s < n_; ++s) slot_[particle_at_[s]] = s;
  pp_.place(slot_.data(), true);
  pw_.place(slot_.data(), false);
  pp_.index(n_, true);
  pw_.index(n_, false);
}

bool DemSystem::integrate_history(bool on) {
  const bool integrated = on && pp_.history;
  for (ContactList* list : {&pp_, &pw_}) {
    list->integrated = integrated;
    // A restored system keeps the paths of its checkpoint.
    if (static_cast<int>(list->path.size()) != (integrated ? list->size() : 0)) {
      list->path.assign(integrated ? list->size() : 0, 0.0);
      list->trial_path = list->path;
    }
    if (!integrated) list->stage_path = list->path_rate = nullptr;
  }
  return integrated;
}

void DemSystem::initial_history(double* s) const {
  std::copy(pp_.path.begin(), pp_.path.end(), s);
  std::copy(pw_.path.begin(), pw_.path.end(), s + pp_.size());
}

void DemSystem::accept(double) {
  pp_.commit();
  pw_.commit();
  committed_angle_.swap(trial_angle_);
  committed_time_ = trial_time_;
}


// One force evaluation, stage by stage. Under IMEX, conduction alone is the implicit part
// (linear in the temperatures); everything else is explicit.
void DemSystem::evaluate(double t, const double* y, double* ydot, Part part, const double* temps) {
  if (part == Part::implicit_only || part == Part::jacobian) {
    implicit_conduction(t, y, ydot, temps, part == Part::implicit_only);
    latest_conducted_ = false;  // the conductances are still the full evaluation's, but not its state's
    return;
  }
  Evaluation e = begin_evaluation(t, y, ydot);
  e.conduct = thermal_ && part == Part::all;
  if (heat_by_step_ && part == Part::all) {
    heat_work_.swap(heat_work_before_);
    heat_work_.assign(pp_.size() + pw_.size(), {});
  }
  particle_contact_forces(e);
  if (e.threaded) rows_to_particles(e);
  wall_contact_forces(e);
  if (e.conduct) {
    pw_.conductance.resize(pw_.size());
    e.heat_walls =
        conduct_walls(t, y, y + temperature_at(), {nullptr, sums_.data(), slot_.data()}, true, pw_.conductance.data());
  }
  latest_conducted_ = e.conduct;
  if (has_attached_ || bodies()) {
    const StageTimer timer(profile_, Stage::wall_contacts);  // what the walls' particles and bodies do
    if (has_attached_) attached_particles(e);
    if (bodies()) wall_bodies(e, ydot);
  }
  accelerations(e);
  close_ledger(e, ydot);
}

// dq/dt = v; the work forces of the walls' ledger zeroed (the particle contacts stage zeroes the
// sums the contact stages add to: prepare_particles()).
DemSystem::Evaluation DemSystem::begin_evaluation(double t, const double* y, double* ydot) {
  const int nq = layout_.nq;
  std::copy_n(y + nq, nq, ydot);
  Evaluation e;
  e.t = t;
  e.state = y;
  e.x = y + x_at();
  e.y = y + y_at();
  e.angle = rotates_ ? y + angle_at() : nullptr;
  e.vx = y + vx_at();
  e.vy = y + vy_at();
  e.w = rotates_ ? y + omega_at() : nullptr;
  e.fx = ydot + vx_at();
  e.fy = ydot + vy_at();
  e.torque = rotates_ ? ydot + omega_at() : nullptr;
  // Heat (thermal scenes only): dissipation turned to heat by the contact stages; conduction
  // (the implicit part under IMEX) by its own.
  if (thermal_) e.heat = ydot + temperature_at();
  e.gd = work_force_.data();
  e.g = e.gd + nq;
  if (works_ == 3) {
    e.gw = e.gd + 2 * nq;
    std::fill_n(e.gw, nq, 0.0);
  }
  e.threaded = runs_threaded(pp_.size());
  if (pp_.history) {
    std::copy_n(e.angle, n_, trial_angle_.data());
    trial_time_ = t;
  }
  if (pp_.integrated) {  // the slip paths after the layout's components: pairs, then walls
    for (auto [list, at] : {std::pair{&pp_, layout_.size()}, std::pair{&pw_, layout_.size() + pp_.size()}}) {
      list->stage_path = y + at;
      list->path_rate = ydot + at;
      std::copy_n(y + at, list->size(), list->trial_path.data());
    }
  }
  return e;
}

// Each particle's sums, from its slot, to its acceleration (gravity added), its work forces and
// its rate of temperature change.
void DemSystem::accelerations(Evaluation& e) {
  const double gx = scene_.gravity.x, gy = scene_.gravity.y;
  const ParticleSum* sums = sums_.data();
  const int* slot = slot_.data();
#pragma omp parallel for schedule(static) if (parallel_worthwhile(n_))
  for (int i = 0; i < n_; ++i) {
    const ParticleSum& s = sums[slot[i]];
    e.fx[i] = s.fx * inv_mass_[i] + gx;
    e.fy[i] = s.fy * inv_mass_[i] + gy;
    e.gd[i] = s.dx;
    e.gd[n_ + i] = s.dy;
    e.g[i] = s.gx;
    e.g[n_ + i] = s.gy;
    if (e.torque) {
      e.g[2 * n_ + i] = -s.torque;  // every contact torque is friction's or rolling resistance's: that ledger's
      e.torque[i] = s.torque * inv_inertia_[i];
    }
    if (e.heat) e.heat[i] = s.heat * inv_capacity_[i];
  }
  // An attached particle follows its wall: no spin change, the wall's acceleration at its place
  // (a turning wall's centripetal one, a wall body's own).
  for (int i : attached_list_) {
    const int w = scene_.attached[i];
    Vec2 a;
    if (w >= 0) {
      const WallMotion& m = scene_.walls[w].motion;
      a = m.acceleration_at({e.x[i], e.y[i]}, e.t);
      if (body_of_wall_[w] >= 0) a = m.along_load(body_acceleration_[body_of_wall_[w]]);
    }
    e.fx[i] = a.x;
    e.fy[i] = a.y;
    if (e.torque) e.torque[i] = 0;
  }
}

// Forces on attached particles are forces on their walls: summed into the walls' loads, and the
// power they take from the particles pushing them is the walls' work.
void DemSystem::attached_particles(Evaluation& e) {
  for (int i : attached_list_) {
    const ParticleSum& s = sums_[slot_[i]];
    const Vec2 f{s.fx, s.fy};
    const double torque = e.torque ? s.torque : 0.0;
    e.walls_work -= f.x * e.vx[i] + f.y * e.vy[i] + (e.torque ? torque * e.w[i] : 0.0);
    e.gw[i] -= f.x;
    e.gw[n_ + i] -= f.y;
    if (e.torque) e.gw[2 * n_ + i] -= torque;
    const int w = scene_.attached[i];
    if (w < 0) continue;
    WallLoad& load = wall_loads_[w];
    load.force = load.force + f;
    load.torque += cross(cell_.image_near({e.x[i], e.y[i]}, wall_centre_[w]) - wall_centre_[w], f) + torque;
    load.power -= f.x * e.vx[i] + f.y * e.vy[i] + (e.torque ? torque * e.w[i] : 0.0);
  }
}

// A load-controlled wall under the particles' force and its load (WallMotion::body_acceleration).
void DemSystem::wall_bodies(Evaluation& e, double* ydot) {
  for (int k = 0; k < bodies(); ++k) {
    const WallMotion& m = scene_.walls[body_wall_[k]].motion;
    body_acceleration_[k] = m.body_acceleration(wall_loads_[body_wall_[k]].force, e.state[body_speed_at() + k]);
    ydot[body_speed_at() + k] = body_acceleration_[k];
  }
}

void DemSystem::close_ledger(const Evaluation& e, double* ydot) {
  double* ledger = ydot + ledger_at();
  ledger[ledger_damping] = e.damping;
  ledger[ledger_friction] = e.friction_work;
  ledger[ledger_walls] = e.walls_work;
  if (e.heat) {
    ledger[ledger_heat_walls] = e.heat_walls;
    ledger[ledger_heat_generated] = e.heat_generated;
  }
  max_overlap_fraction_ = e.worst;
}

// IMEX's implicit part: conduction alone (linear in the temperatures `temps`); the walls' heat
// sources enter the implicit part, not its Jacobian. The heat the walls deliver is linear in the
// temperatures too: its ledger rate has a Jacobian row, -sum H_w v_i, which a scheme that
// corrects its slopes with the Jacobian needs to keep the ledger closed.
void DemSystem::implicit_conduction(double t, const double* y, double* ydot, const double* temps, bool wall_sources) {
  std::fill_n(ydot, state_size(), 0.0);
  if (moving_walls_) update_walls(t, y);
  double* heat = ydot + temperature_at();
  const double heat_walls = conduct(t, y, temps ? temps : y + temperature_at(), heat, wall_sources);
  for (int i = 0; i < n_; ++i) heat[i] *= inv_capacity_[i];
  ydot[ledger_at() + ledger_heat_walls] = heat_walls;
}

std::vector<double> DemSystem::absolute_tolerances(const StepControl& c) const {
  std::vector<double> atol(state_size(), c.atol);
  auto fill = [&](int from, int count, double value) {
    if (from >= 0 && std::isfinite(value)) std::fill_n(atol.begin() + from, count, value);
  };
  fill(x_at(), 2 * n_, c.atol_position);
  fill(angle_at(), n_, c.atol_angle);
  fill(vx_at(), 2 * n_, c.atol_velocity);
  fill(omega_at(), n_, c.atol_velocity);
  fill(temperature_at(), n_, c.atol_temperature);
  fill(body_at(), bodies(), c.atol_position);
  fill(body_speed_at(), bodies(), c.atol_velocity);
  fill(layout_.size(), history_size(), c.atol_position);  // slip paths: lengths
  return atol;
}


}  // namespace kiln
