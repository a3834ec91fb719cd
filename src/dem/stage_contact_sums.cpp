// The contact sums stage of a threaded evaluation: each particle sums the rows of its particle
// contacts (ContactRow, HeatRow) into its force, torque, heat and work forces, at its slot, in the
// order of the list: first the pairs where its slot is the higher (their lower slot is smaller, so
// they come first), then those where it is the lower. Whichever thread has a particle, its bits
// are those of one thread adding each row to its two particles as the contact loop makes it
// (DemSystem::add_row). The wall stage adds its rows after this one, as it does on one thread.
#include "src/dem/dem_system.h"
#include "src/base/parallel.h"

namespace kiln {

void DemSystem::rows_to_particles(Evaluation& e) {
  const StageTimer timer(profile_, Stage::particle_contacts);
  const ContactRow* pair = pp_.rows.data();
  const HeatRow* pair_heat = e.heat ? pp_.heat_rows.data() : nullptr;
  const int *by_i = pp_.by_i.data(), *by_j = pp_.by_j.data(), *by_j_rows = pp_.by_j_rows.data();
  const int* slot_of_i = pp_.si.data();
  ParticleSum* sums = sums_.data();
#pragma omp parallel for schedule(static)
  for (int k = 0; k < n_; ++k) {
    ParticleSum s{};
    // The particle at slot k is the pair's i or its j.
    auto add = [&](int p) {
      const bool is_i = slot_of_i[p] == k;
      add_row_to(s, pair[p], is_i);
      if (pair_heat) s.heat += is_i ? pair_heat[p].to_i : pair_heat[p].to_j;
    };
    for (int q = by_j[k]; q < by_j[k + 1]; ++q) add(by_j_rows[q]);
    for (int p = by_i[k]; p < by_i[k + 1]; ++p) add(p);
    sums[k] = s;
  }
}

}  // namespace kiln
