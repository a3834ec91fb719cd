// Heat made by dissipation, booked by the step under the Verlet schemes.
//
// Their ledger books the works of the dashpots and of friction as the trapezoid of the work
// forces along the step's displacement (VerletFamily::book_work). The temperatures integrated
// the heat rates at the velocities the forces saw instead (the prediction, or v_n+1/2), so the
// heat drifted from beta times the ledger's dissipation at first order in dt (N3: 1.47 % at its
// step). Here each contact's heat is its work over the step by the ledger's own rule: the rows of
// the previous and the latest evaluation on the step's displacement, 1/2 scale (h_n + h_n+1) . dir,
// plus the rests by the scheme's weights. Summed over the contacts that is the ledger's trapezoid
// term by term, so the two agree to round-off. A contact is matched with nothing across the two
// evaluations: each row stands for its own half of the trapezoid.
#include "src/dem/dem_system.h"

namespace kiln {

void DemSystem::book_contact_works(const double* dir, double scale, double rest_weight_old, double rest_weight_new,
                                   double* z) {
  if (!heat_by_step_) return;
  const int n = n_, z_at = 2 * layout_.nq;
  const double* turned = rotates_ ? dir + 2 * n : nullptr;
  double* temperature = z + (temperature_at() - z_at);
  double made = 0;
  auto book = [&](const std::vector<HeatWork>& works, double rest_weight) {
    for (const HeatWork& c : works) {
      if (c.i < 0) continue;  // not touching at that evaluation
      double along = c.hx * dir[c.i] + c.hy * dir[n + c.i] - (turned ? c.ti * turned[c.i] : 0.0);
      if (c.j >= 0) along -= c.hx * dir[c.j] + c.hy * dir[n + c.j] + (turned ? c.tj * turned[c.j] : 0.0);
      const double q = 0.5 * scale * along + rest_weight * c.rest;
      temperature[c.i] += c.share * q * inv_capacity_[c.i];
      if (c.j >= 0) temperature[c.j] += (1 - c.share) * q * inv_capacity_[c.j];
      made += q;
    }
  };
  book(heat_work_before_, rest_weight_old);
  book(heat_work_, rest_weight_new);
  z[ledger_at() - z_at + ledger_heat_generated] += made;
}

void DemSystem::heat_work_state(SnapshotFields& f) {
  constexpr int fields = 8;
  std::vector<double> flat;
  if (f.saving())
    for (const HeatWork& c : heat_work_)
      flat.insert(flat.end(), {static_cast<double>(c.i), static_cast<double>(c.j), c.share, c.hx, c.hy, c.ti, c.tj, c.rest});
  f.field("heat_work", flat);
  if (f.saving()) return;
  if (flat.size() % fields != 0) throw InputError("the checkpoint's heat_work is not a list of contact rows");
  heat_work_.resize(flat.size() / fields);
  for (std::size_t k = 0; k < heat_work_.size(); ++k) {
    const double* r = flat.data() + fields * k;
    const int i = static_cast<int>(r[0]), j = static_cast<int>(r[1]);
    if (i < -1 || i >= n_ || j < -1 || j >= n_)
      throw InputError("the checkpoint's heat_work names particles this scene does not have");
    heat_work_[k] = {i, j, r[2], r[3], r[4], r[5], r[6], r[7]};
  }
}

}  // namespace kiln
