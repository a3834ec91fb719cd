// The wall contacts stage: the walls moved to where they are at t; every (particle, segment)
// candidate that touches gets its forces from
// the kernel. The contact point is at the disc's lever arm, its full radius: the wall's velocity
// there enters the relative velocity, and the work the wall does on the particle is F . u_wall
// plus the rolling couple times the wall's spin. What the particles do to each wall (force,
// torque about its centre, power delivered) is summed into its load. Wall contacts are few
// (a surface's worth): the stage runs on one thread and adds each contact's row to its particle,
// in the order of the list, after the particle contacts' sums.
#include "src/dem/contact_kernel.h"

namespace kiln {

void DemSystem::wall_contact_forces(Evaluation& e) {
  const StageTimer timer(profile_, Stage::wall_contacts);
  if (moving_walls_) update_walls(e.t, e.state);
  const bool history = pp_.history;
  for (WallLoad& load : wall_loads_) load = {};
  const bool thermal = e.heat != nullptr;
  const ContactArrays list = pw_.arrays();
  ParticleSum* sums = sums_.data();
  for (int p = 0, np = pw_.size(); p < np; ++p) {
    const int i = pw_.i[p], sgi = pw_.j[p];
    const double r = radius_[i];
    WallHit hit;
    // An attached particle is part of a wall: walls do not touch walls.
    if ((events_ && !pw_.active[p]) || attached(i) || !wall_hit(e.x, e.y, seg_a_, seg_b_, i, sgi, hit, events_)) {
      if (history) forget(list, p);
      continue;
    }
    const Vec2 n = hit.normal;
    const int wall = scene_.segments[sgi].wall;
    const WallMotion& motion = scene_.walls[wall].motion;
    const Vec2 point = image_at(e.x, e.y, i, seg_a_[sgi], seg_b_[sgi]) + r * n;
    const Vec2 u = wall_point_velocity(wall, point, e.t, e.state);
    const double wall_spin = motion.spin();
    ContactKinematics c;
    // rho from the continuous position: a wrap across a periodic edge leaves the spring whole.
    const Vec2 rho = Vec2{e.x[i], e.y[i]} - seg_a_[sgi];  // from a point fixed on the wall
    c.frame = {n.x, n.y, dot(rho, perp(n)), dot(rho, n)};
    c.rv = {e.vx[i] - u.x, e.vy[i] - u.y};
    c.overlap = hit.overlap;
    c.i = i;
    c.j = -1;
    if (history) {
      c.arm_i = c.arm_then = r;
      c.w_i = e.w[i];
      c.w_other = wall_spin;
      c.spun_i = e.angle[i] - committed_angle_[i];
      c.spun_other = wall_spin * (e.t - committed_time_);
    }
    const ContactForces f = contact<true, void>(list, p, c);
    const double power = f.fx * u.x + f.fy * u.y + f.couple * wall_spin;
    // work_rate = -F_t ((v_i - u) . t + r w_i) - M (w_i - wall spin): the u and spin parts are no g
    const ContactRow row = row_of(f, n.x, n.y, r, 0.0);
    add_row(sums, list.si[p], -1, row);
    e.damping += f.damping_power;
    e.friction_work += f.work_rate;
    e.walls_work += power;
    if (const int k = body_of_wall_[wall]; k >= 0)  // the part through the body's speed: a work
      e.gw[body_at() + k] += motion.component_along_load({f.fx, f.fy});
    WallLoad& load = wall_loads_[wall];
    load.force = load.force - Vec2{f.fx, f.fy};
    load.torque += cross(point - wall_centre_[wall], Vec2{-f.fx, -f.fy}) - f.couple;
    load.power += power;
    if (thermal) {  // the wall keeps its share
      const double share = laws_[pw_.law[p]].heat_share;
      const double made = share * heat_made(f.work_rate, f.damping_power);
      if (heat_by_step_) {  // the wall's velocity and spin go into the rest
        HeatWork w = heat_work(i, -1, 1.0, row);
        w.hx *= share;
        w.hy *= share;
        w.ti *= share;
        w.rest = made - (w.hx * e.vx[i] + w.hy * e.vy[i] - (e.w ? w.ti * e.w[i] : 0.0));
        heat_work_[pp_.size() + p] = w;
      } else {
        add_heat_row(sums, list.si[p], -1, {made, 0.0});
        e.heat_generated += made;
      }
    }
    e.worst = std::max(e.worst, hit.overlap * inv_radius_[i]);
  }
}

}  // namespace kiln
