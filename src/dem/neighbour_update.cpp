// The neighbour update stage: candidate lists from Box2D's tree, kept while no particle (or
// wall) can have closed a skin's gap; the contact coefficients of each candidate; the contact
// frames of contacts first seen touching.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "contact/in_series.h"
#include "src/dem/dem_system.h"
#include "src/geometry/curve_order.h"
#include "src/base/parallel.h"

namespace kiln {
namespace {

// The slots a contact loop may reach back over and still find in cache: the kinematics and sums
// of 4,096 particles (512 KB) fit a core's L2 cache (reorder_slots()).
constexpr int slot_window = 4096;

}  // namespace

void DemSystem::prepare(double t, const double* y, double lookahead) {
  // A step that carries particles further than the base skin allows gets a wider skin for its
  // lists: covers() wants 2 (2 lookahead v) < skin; half as much again for the accelerations.
  if (!built_ || !covers(t, y, lookahead)) rebuild(t, y, 6 * lookahead * fastest_speed(y));
}

// (Maxima do not depend on the order they are taken in: these loops share out freely.)
double DemSystem::fastest_speed(const double* y) const {
  const double *vx = y + vx_at(), *vy = y + vy_at();
  double v2max = 0;
#pragma omp parallel for schedule(static) reduction(max : v2max) if (parallel_worthwhile(n_))
  for (int i = 0; i < n_; ++i) v2max = std::max(v2max, vx[i] * vx[i] + vy[i] * vy[i]);
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
    wall_travel = std::max(wall_travel, scene_.walls[w].motion.max_displacement(scene_.segments, static_cast<int>(w),
                                                                                t, t_reached) +
                                            norm(body_offset(static_cast<int>(w), reached) - body_offset(static_cast<int>(w), y)));
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
#pragma omp parallel for schedule(static) reduction(max : d2max, v2max) if (parallel_worthwhile(n_))
  for (int i = 0; i < n_; ++i) {
    const double dx = px[i] - x_ref_[i], dy = py[i] - y_ref_[i];
    d2max = std::max(d2max, dx * dx + dy * dy);
    v2max = std::max(v2max, vx[i] * vx[i] + vy[i] * vy[i]);
  }
  const double moved = std::sqrt(d2max) + 2 * lookahead * std::sqrt(v2max);
  double wall_moved = 0;
  for (size_t w = 0; w < scene_.walls.size(); ++w) {
    // A wall body: how far it went since the rebuild, and as far again as its speed takes it.
    const int k = body_of_wall_[w];
    const double body = k < 0 ? 0.0 : std::abs(y[body_at() + k] - body_ref_[k]) + 2 * lookahead * std::abs(y[body_speed_at() + k]);
    wall_moved = std::max(wall_moved, scene_.walls[w].motion.max_displacement(scene_.segments, static_cast<int>(w),
                                                                              t_ref_, t + lookahead) + body);
  }
  const double skin = broadphase_.skin();
  return 2 * moved < skin && moved + wall_moved < skin;
}

void DemSystem::rebuild(double t, const double* y, double skin) {
  const StageTimer timer(profile_, Stage::neighbour_update);
  const double* px = y + x_at();
  const double* py = y + y_at();
  broadphase_.set_skin(std::max(base_skin_, skin));
  // The tree sees each particle's place in the cell, in slot order: its pairs come out as pairs of
  // slots, sorted as the lists keep them.
  places_by_slot(px, py);
  broadphase_.particle_pairs(slot_x_.data(), slot_y_.data(), slot_r_.data(), n_, cell_, candidates_);
  if (reorder_slots()) {
    places_by_slot(px, py);
    broadphase_.particle_pairs(slot_x_.data(), slot_y_.data(), slot_r_.data(), n_, cell_, candidates_);
    ranked_share_ = share_apart(candidates_, slot_window);
  }
  pp_.replace(candidates_, n_, true, particle_at_.data(), slot_.data());
  set_coefficients(pp_, false);
  update_walls(t, y);
  broadphase_.wall_pairs(slot_x_.data(), slot_y_.data(), slot_r_.data(), n_, seg_a_, seg_b_, cell_, candidates_);
  pw_.replace(candidates_, n_, false, particle_at_.data(), slot_.data());
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
  std::copy_n(y + body_at(), bodies(), body_ref_.data());
  t_ref_ = t;
  built_ = true;
  ++rebuilds_;
}

void DemSystem::places_by_slot(const double* px, const double* py) {
  slot_x_.resize(n_);
  slot_y_.resize(n_);
  slot_r_.resize(n_);
  for (int s = 0; s < n_; ++s) {
    const int i = particle_at_[s];
    const Vec2 p = place(px, py, i);
    slot_x_[s] = p.x;
    slot_y_[s] = p.y;
    slot_r_[s] = radius_[i];
  }
}

// The slots are kept while nine in ten candidate pairs lie within a cache's worth of slots of
// each other (slot_window). Past that the particles are ranked along a Hilbert curve of their
// places (curve_order.h): the
// settled 100,000-disc bench pile so ranked has none of its pairs further apart than that (1.9 %
// more than 1,024 slots); numbered at random, (1 - 4,096 / 100,000)^2 = 92 %. The tree is then
// filled again in the new order (a rebuild from scratch, as rare as the pile's mixing makes it).
// A ranking that left more than a twentieth apart is repeated only once the share has doubled
// (ranked_share_): one disc a hundred kilometres from a pile put the whole pile into one cell of
// the curve, and every rebuild ranked it again, in vain, at ten times a rebuild's cost.
bool DemSystem::reorder_slots() {
  constexpr double drifted = 0.1;
  if (n_ <= slot_window || share_apart(candidates_, slot_window) <= std::max(drifted, 2 * ranked_share_)) return false;
  std::vector<int>& by_curve = curve_order_;
  hilbert_order(slot_x_.data(), slot_y_.data(), n_, by_curve, curve_keys_);
  for (int r = 0; r < n_; ++r) by_curve[r] = particle_at_[by_curve[r]];  // slots of now to particles
  particle_at_.swap(by_curve);
  for (int r = 0; r < n_; ++r) slot_[particle_at_[r]] = r;
  broadphase_.forget_particles();
  ++reorders_;
  return true;
}

// Contacts present at the start of a run (or touching when they enter the list) are measured
// from the state they are first seen in: their springs start there, unstretched.
void DemSystem::frame_new_contacts(double t, const double* y) {
  const double *px = y + x_at(), *py = y + y_at();
  for (int p = 0; p < pp_.size(); ++p) {
    if (pp_.frame[p].known()) continue;
    const int i = pp_.i[p], j = pp_.j[p];
    const Vec2 dv = separation(px, py, i, j);
    const double rsum = radius_[i] + radius_[j];
    // Most candidates without a frame are apart: no hypot for them (the margin keeps every pair
    // hypot could find touching).
    if (dv.x * dv.x + dv.y * dv.y > rsum * rsum * (1 + 1e-12)) continue;
    const double d = std::hypot(dv.x, dv.y);
    const double overlap = rsum - d;
    if (overlap <= 0) continue;
    pp_.frame[p] = pp_.trial_frame[p] = {dv.x / d, dv.y / d, 0.0, -d};
  }
  update_walls(t, y);
  for (int p = 0; p < pw_.size(); ++p) {
    if (pw_.frame[p].known()) continue;
    const int i = pw_.i[p], sgi = pw_.j[p];
    WallHit hit;
    if (!wall_hit(px, py, seg_a_, seg_b_, i, sgi, hit, false)) continue;
    // From the continuous position: a wrap across a periodic edge leaves rho, and the spring, whole.
    const Vec2 rho = Vec2{px[i], py[i]} - seg_a_[sgi];
    pw_.frame[p] = pw_.trial_frame[p] = {hit.normal.x, hit.normal.y, dot(rho, perp(hit.normal)), dot(rho, hit.normal)};
  }
}

void DemSystem::set_coefficients(ContactList& list, bool walls) {
  const int nm = scene_.n_materials();
  for (int p = 0; p < list.size(); ++p) {
    const int i = list.i[p], j = list.j[p];
    const int mi = material_[i];
    const int mj = walls ? scene_.walls[scene_.segments[j].wall].material : material_[j];
    // A wall is a flat body of infinite mass: m_eff = m_i and R* = r_i.
    const double m_eff = walls ? mass_[i] : contact::in_series(mass_[i], mass_[j]);
    const double r_eff = walls ? radius_[i] : contact::in_series(radius_[i], radius_[j]);
    const contact::NormalLaw nl = laws_[mi * nm + mj].normal_law(m_eff, r_eff);
    list.law[p] = static_cast<uint16_t>(mi * nm + mj);
    list.k[p] = nl.k;
    list.c[p] = nl.c;
  }
}

}  // namespace kiln
