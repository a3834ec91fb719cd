// The contact sums stage of a threaded evaluation: each particle sums the rows of its particle
// contacts (ContactRow, HeatRow) into its force, torque, heat and work forces in the order of the
// list: first the pairs where it is j (their i is smaller, so they come first), then those where it
// is i. Whichever thread has a particle, its bits are those of one thread adding each row to its
// two particles as the contact loop makes it (DemSystem::add_row). The wall stage adds its rows
// after this one, as it does on one thread.
#include "src/dem/dem_system.h"
#include "src/base/parallel.h"

namespace kiln {

void DemSystem::rows_to_particles(Evaluation& e) {
  const StageTimer timer(profile_, Stage::particle_contacts);
  const ContactRow* pair = pp_.rows.data();
  const HeatRow* pair_heat = e.heat ? pp_.heat_rows.data() : nullptr;
  const int *by_i = pp_.by_i.data(), *by_j = pp_.by_j.data(), *by_j_rows = pp_.by_j_rows.data();
#pragma omp parallel for schedule(static)
  for (int i = 0; i < n_; ++i) {
    double fx = 0, fy = 0, torque = 0, gx = 0, gy = 0, dx = 0, dy = 0, heat = 0;
    for (int k = by_j[i]; k < by_j[i + 1]; ++k) {
      const int p = by_j_rows[k];
      const ContactRow& r = pair[p];
      fx -= r.fx;
      fy -= r.fy;
      torque += r.torque_j;
      gx -= r.gx;
      gy -= r.gy;
      dx -= r.dx;
      dy -= r.dy;
      if (pair_heat) heat += pair_heat[p].to_j;
    }
    for (int p = by_i[i]; p < by_i[i + 1]; ++p) {
      const ContactRow& r = pair[p];
      fx += r.fx;
      fy += r.fy;
      torque += r.torque_i;
      gx += r.gx;
      gy += r.gy;
      dx += r.dx;
      dy += r.dy;
      if (pair_heat) heat += pair_heat[p].to_i;
    }
    e.fx[i] = fx;
    e.fy[i] = fy;
    e.gd[i] = dx;
    e.gd[n_ + i] = dy;
    e.g[i] = gx;
    e.g[n_ + i] = gy;
    if (e.torque) e.torque[i] = torque;
    if (e.heat) e.heat[i] = heat;
  }
}

}  // namespace kiln
