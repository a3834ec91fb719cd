// The particle contacts stage: every candidate pair that touches (or, with contact events, acts)
// gets its contact forces from the kernel; they are applied to both particles, with their lever
// arms, and the dissipation goes to the ledger (and to heat where the scene says so).
#include "src/contact_kernel.h"

namespace kiln {

void DemSystem::particle_contact_forces(Evaluation& e) {
  const StageTimer timer(profile_, Stage::particle_contacts);
  const bool history = pp_.history;
  for (int p = 0, np = pp_.size(); p < np; ++p) {
    const int i = pp_.i[p], j = pp_.j[p];
    const Vec2 d = separation(e.x, e.y, i, j);
    const double rsum = radius_[i] + radius_[j];
    const double d2 = d.x * d.x + d.y * d.y;
    // With contact events the acting set is locked for the step: an acting contact keeps its
    // (continued) law past separation until its release is located, a new one waits for its onset.
    // Two particles of walls (attached or fixed) do not touch: walls do not touch walls.
    if ((events_ ? !pp_.active[p] : d2 >= rsum * rsum) || (has_attached_ && attached(i) && attached(j))) {
      if (history) forget(pp_, p);
      continue;
    }
    const double dist = std::sqrt(d2);
    const double inv_d = 1 / dist;
    const double nx = d.x * inv_d, ny = d.y * inv_d;  // from i to j
    ContactKinematics c;
    c.frame = {nx, ny, 0.0, -dist};
    c.rv = {e.vx[i] - e.vx[j], e.vy[i] - e.vy[j]};
    c.overlap = rsum - dist;
    c.i = i;
    c.j = j;
    if (history) {
      c.arm_i = contact::pair_arm(radius_[i], c.overlap);
      c.arm_other = contact::pair_arm(radius_[j], c.overlap);
      c.arm_then = contact::pair_arm(radius_[i], rsum + pp_.frame[p].rho_n);
      c.w_i = e.w[i];
      c.w_other = e.w[j];
      c.spun_i = e.angle[i] - committed_angle_[i];
      c.spun_other = e.angle[j] - committed_angle_[j];
    }
    const ContactForces f = contact(pp_, p, c);
    e.fx[i] += f.fx;
    e.fy[i] += f.fy;
    e.fx[j] -= f.fx;
    e.fy[j] -= f.fy;
    if (history) {
      const double ti = c.arm_i * f.tangential + f.couple, tj = c.arm_other * f.tangential - f.couple;
      e.torque[i] += ti;
      e.torque[j] += tj;
      // work_rate = -F_t ((v_i - v_j) . t + arm_i w_i + arm_j w_j) - M (w_i - w_j)
      e.g[i] += f.tangential * ny;
      e.g[n_ + i] -= f.tangential * nx;
      e.g[j] -= f.tangential * ny;
      e.g[n_ + j] += f.tangential * nx;
      e.g[2 * n_ + i] -= ti;
      e.g[2 * n_ + j] -= tj;
    }
    e.gd[i] += f.dashpot * nx;
    e.gd[n_ + i] += f.dashpot * ny;
    e.gd[j] -= f.dashpot * nx;
    e.gd[n_ + j] -= f.dashpot * ny;
    e.damping += f.damping_power;
    e.friction_work += f.work_rate;
    if (e.heat) make_heat(e, f.work_rate, f.damping_power, i, j, laws_[pp_.law[p]].heat_share);
    e.worst = std::max(e.worst, c.overlap * std::max(inv_radius_[i], inv_radius_[j]));
  }
}

}  // namespace kiln
