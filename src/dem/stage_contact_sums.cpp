// The contact sums stage: each particle sums the rows of its contacts (ContactRow, HeatRow) into
// its force, torque, heat and work forces, in a fixed order (the pairs where it is i, those where
// it is j, then its walls), so the bits do not depend on how the particles are shared among the
// threads.
#include "src/dem/dem_system.h"
#include "src/base/parallel.h"

namespace kiln {

void DemSystem::rows_to_particles(Evaluation& e) {
  const StageTimer timer(profile_, Stage::particle_contacts);
  const ContactRow* pair = pp_.rows.data();
  const ContactRow* wall = pw_.rows.data();
  const HeatRow* pair_heat = e.heat ? pp_.heat_rows.data() : nullptr;
  const HeatRow* wall_heat = e.heat ? pw_.heat_rows.data() : nullptr;
  const int *by_i = pp_.by_i.data(), *by_j = pp_.by_j.data(), *by_j_rows = pp_.by_j_rows.data();
  const int* wall_by_i = pw_.by_i.data();
#pragma omp parallel for schedule(static) if (parallel_worthwhile(n_))
  for (int i = 0; i < n_; ++i) {
    double fx = 0, fy = 0, torque = 0, gx = 0, gy = 0, dx = 0, dy = 0, heat = 0;
    // The rows where the particle is the contact's first body (a pair's i, or against a wall).
    auto add_as_first = [&](const ContactRow* rows, const HeatRow* heat_rows, int begin, int end) {
      for (int p = begin; p < end; ++p) {
        const ContactRow& r = rows[p];
        fx += r.fx;
        fy += r.fy;
        torque += r.torque_i;
        gx += r.gx;
        gy += r.gy;
        dx += r.dx;
        dy += r.dy;
        if (heat_rows) heat += heat_rows[p].to_i;
      }
    };
    add_as_first(pair, pair_heat, by_i[i], by_i[i + 1]);
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
    add_as_first(wall, wall_heat, wall_by_i[i], wall_by_i[i + 1]);
    e.fx[i] = fx;
    e.fy[i] = fy;
    e.gd[i] = dx;
    e.gd[n_ + i] = dy;
    e.g[i] = gx;
    e.g[n_ + i] = gy;
    if (e.torque) {
      e.torque[i] = torque;
      e.g[2 * n_ + i] = -torque;
    }
    if (e.heat) e.heat[i] = heat;
  }
}

}  // namespace kiln
