// The particle contacts stage: every candidate pair that touches (or, with contact events, acts)
// gets its contact forces from the kernel, and writes them, their lever arms' torques, their work
// forces and what they dissipate into its own row (ContactRow); rows_to_particles() then sums
// them per particle. The contacts run on all threads: a row is written by its contact alone, and
// the scalar sums are taken over fixed blocks of contacts in order, so the results are the same
// bits whatever the number of threads. In a thermal scene's full evaluation the row also carries
// the heat conducted through the contact: the geometry is computed once for both.
#include "src/dem/contact_kernel.h"
#include "src/base/parallel.h"

namespace kiln {

void DemSystem::particle_contact_forces(Evaluation& e) {
  const StageTimer timer(profile_, Stage::particle_contacts);
  const bool history = pp_.history;
  const bool thermal = e.heat != nullptr;
  if (thermal) pp_.heat_rows.resize(pp_.size());
  const double* temp = e.conduct ? e.state + temperature_at() : nullptr;
  const int np = pp_.size();
  const int blocks = block_count(np);
  block_sums_.resize(blocks);
#pragma omp parallel for schedule(static) if (parallel_worthwhile(np))
  for (int b = 0; b < blocks; ++b) {
    BlockSums sums;
    for (int p = b * sum_block, end = std::min(np, p + sum_block); p < end; ++p) {
      const int i = pp_.i[p], j = pp_.j[p];
      const Vec2 d = separation(e.x, e.y, i, j);
      const double rsum = radius_[i] + radius_[j];
      const double d2 = d.x * d.x + d.y * d.y;
      ContactRow& row = pp_.rows[p];
      // With contact events the acting set is locked for the step: an acting contact keeps its
      // (continued) law past separation until its release is located, a new one waits for its onset.
      const bool acting = events_ ? pp_.active[p] != 0 : d2 < rsum * rsum;
      // Two particles of walls (attached or fixed) do not push each other: walls do not touch
      // walls. They still conduct heat.
      const bool walls_both = has_attached_ && attached(i) && attached(j);
      if (!acting || walls_both) {
        if (history) forget(pp_, p);
        row = {};
        if (thermal) pp_.heat_rows[p] = {};
        if (!acting || !temp) continue;
      }
      const double dist = std::sqrt(d2);
      const double overlap = rsum - dist;
      if (temp) {
        const double h = touching_pair_conductance(p, dist, overlap);
        const double q = h * (temp[j] - temp[i]);
        pp_.heat_rows[p] = {q, -q, h};
        if (walls_both) continue;
      }
      const double inv_d = 1 / dist;
      const double nx = d.x * inv_d, ny = d.y * inv_d;  // from i to j
      ContactKinematics c;
      c.frame = {nx, ny, 0.0, -dist};
      c.rv = {e.vx[i] - e.vx[j], e.vy[i] - e.vy[j]};
      c.overlap = overlap;
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
      row.fx = f.fx;
      row.fy = f.fy;
      // work_rate = -F_t ((v_i - v_j) . t + arm_i w_i + arm_j w_j) - M (w_i - w_j)
      row.torque_i = c.arm_i * f.tangential + f.couple;
      row.torque_j = c.arm_other * f.tangential - f.couple;
      row.gx = f.tangential * ny;
      row.gy = -f.tangential * nx;
      row.dx = f.dashpot * nx;
      row.dy = f.dashpot * ny;
      sums.damping += f.damping_power;
      sums.friction_work += f.work_rate;
      if (thermal) {
        const double made = heat_made(f.work_rate, f.damping_power);
        const double share = laws_[pp_.law[p]].heat_share;
        HeatRow& heat = pp_.heat_rows[p];
        if (!temp) heat = {};
        heat.to_i += share * made;
        heat.to_j += (1 - share) * made;
        sums.heat_generated += made;
      }
      sums.worst = std::max(sums.worst, c.overlap * std::max(inv_radius_[i], inv_radius_[j]));
    }
    block_sums_[b] = sums;
  }
  add_block_sums(e);
}

}  // namespace kiln
