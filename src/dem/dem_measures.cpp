// What the system's state measures: the energy ledger and the contacts in touch.
#include "src/dem/contact_kernel.h"

namespace kiln {

EnergyLedger DemSystem::energy(double t, const double* y) const {
  EnergyLedger e;
  const double *px = y + x_at(), *py = y + y_at(), *vx = y + vx_at(), *vy = y + vy_at();
  for (int i = 0; i < n_; ++i) {
    if (attached(i)) continue;  // part of a wall: outside the particles' balance
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
    const ContactCoefficients& lf = laws_[list.law[p]];
    const contact::NormalLaw nl = lf.normal_law_of(list.k[p], list.c[p]);
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
    const int j = pp_.j[p];
    const double overlap = pair_overlap(px, py, p);
    if (overlap > 0 && !(attached(pp_.i[p]) && attached(j))) add(pp_, p, j, overlap);
  }
  for (int p = 0; p < pw_.size(); ++p) {
    const int i = pw_.i[p];
    WallHit hit;
    if (wall_hit(px, py, a, b, i, pw_.j[p], hit, false))
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

DemSystem::ContactCount DemSystem::count_contacts(double t, const double* y) const {
  ContactCount count;
  const double *px = y + x_at(), *py = y + y_at();
  for (int p = 0; p < pp_.size(); ++p) {
    const int i = pp_.i[p], j = pp_.j[p];
    const double rs = radius_[i] + radius_[j];
    const Vec2 d = separation(px, py, i, j);
    count.particle_particle += d.x * d.x + d.y * d.y < rs * rs;
  }
  std::vector<Vec2> a, b;
  wall_geometry(t, y, a, b);
  WallHit hit;
  for (int p = 0; p < pw_.size(); ++p) {
    const int i = pw_.i[p];
    count.particle_wall += wall_hit(px, py, a, b, i, pw_.j[p], hit, false);
  }
  return count;
}

}  // namespace kiln
