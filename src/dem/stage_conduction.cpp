// The conduction stage ([thesis] eq. II.6-II.8): heat through every touching contact and from
// isothermal walls; and the same network as a Jacobian (IMEX) or as frozen links.
#include "src/dem/dem_system.h"

namespace kiln {

// Conductance of candidate pair p, 0 unless its discs touch (and, with contact events, it acts).
double DemSystem::pair_conductance(const double* px, const double* py, int p) const {
  if (events_ && !pp_.active[p]) return 0;
  const int i = pp_.i[p], j = pp_.j[p];
  const Vec2 dv = separation(px, py, i, j);
  const double rsum = radius_[i] + radius_[j];
  const double d2 = dv.x * dv.x + dv.y * dv.y;
  if (d2 >= rsum * rsum) return 0;
  const double d = std::sqrt(d2);
  return touching_conductance(pp_.law[p], pp_.k[p], pp_.c[p], radius_[i], radius_[j], d, rsum - d);
}

// Conductance between particle pw.i[p] and its wall segment (walls at their geometry a, b), 0
// unless they touch; `wall` is set to the wall's index.
double DemSystem::wall_conductance(const double* px, const double* py, const std::vector<Vec2>& a,
                                   const std::vector<Vec2>& b, int p, int& wall) const {
  const int i = pw_.i[p];
  wall = scene_.segments[pw_.j[p]].wall;
  WallHit hit;
  if ((events_ && !pw_.active[p]) || !scene_.walls[wall].temperature.isothermal() ||
      !wall_hit(px, py, a, b, i, pw_.j[p], hit, events_))
    return 0;
  return touching_conductance(pw_.law[p], pw_.k[p], pw_.c[p], radius_[i], INFINITY, radius_[i] - hit.overlap,
                              hit.overlap);
}

// Conduction ([thesis] eq. II.6-II.8): heat[i] += sum_j H_ij (T_j - T_i) + sum_w H_iw (T_w - T_i)
// over isothermal walls, whose temperatures are taken as 0 without `wall_sources` (the Jacobian).
// Returns the heat the walls give (W). Wall geometry must be current (update_walls).
double DemSystem::conduct(double t, const double* y, const double* temp, double* heat, bool wall_sources) const {
  const StageTimer timer(profile_, Stage::conduction);
  const double *px = y + x_at(), *py = y + y_at();
  for (int p = 0, np = pp_.size(); p < np; ++p) {
    const int i = pp_.i[p], j = pp_.j[p];
    const double q = pair_conductance(px, py, p) * (temp[j] - temp[i]);
    heat[i] += q;
    heat[j] -= q;
  }
  return conduct_walls(t, y, temp, {heat}, wall_sources);
}

// The walls' part of conduct(): heat[i] += sum_w H_iw (T_w - T_i); returns the heat the walls give.
// With `conductance`, each candidate's goes there (0 when not touching).
double DemSystem::conduct_walls(double t, const double* y, const double* temp, const HeatSink& heat, bool wall_sources,
                                double* conductance) const {
  const double *px = y + x_at(), *py = y + y_at();
  double heat_walls = 0;
  for (int p = 0, np = pw_.size(); p < np; ++p) {
    int wall = 0;
    const double h = wall_conductance(px, py, seg_a_, seg_b_, p, wall);
    if (conductance) conductance[p] = h;
    if (h == 0) continue;
    const double q = h * ((wall_sources ? scene_.walls[wall].temperature.at(t) : 0.0) - temp[pw_.i[p]]);
    heat[pw_.i[p]] += q;
    heat_walls += q;
  }
  return heat_walls;
}


// Conduction's Jacobian at the latest full evaluation, from the conductances it left per
// candidate: jv's temperatures and heat-from-walls ledger entry (the rest of jv is not touched).
bool DemSystem::latest_implicit_jacobian_times(const double* v, double* jv) {
  if (!latest_conducted_) return false;
  const double* temps = v + temperature_at();
  double* heat = jv + temperature_at();
  std::fill_n(heat, n_, 0.0);
  const int *pi = pp_.i.data(), *pj = pp_.j.data();
  const double* h = pp_.conductance.data();
  for (int p = 0, np = pp_.size(); p < np; ++p) {
    const int i = pi[p], j = pj[p];
    const double q = h[p] * (temps[j] - temps[i]);
    heat[i] += q;
    heat[j] -= q;
  }
  double heat_walls = 0;
  for (int p = 0, np = pw_.size(); p < np; ++p) {
    const double q = -pw_.conductance[p] * temps[pw_.i[p]];
    heat[pw_.i[p]] += q;
    heat_walls += q;
  }
  for (int i = 0; i < n_; ++i) heat[i] *= inv_capacity_[i];
  jv[ledger_at() + ledger_heat_walls] = heat_walls;
  return true;
}

// Conduction's Jacobian: W the heat capacities, S the Laplacian of the contact conductances at
// (t, y) with the wall conductances on its diagonal, and the heat-from-walls row -sum H_iw.
bool DemSystem::diffusion_jacobian(double t, const double* y, DiffusionJacobian& out) const {
  if (!thermal_) return false;
  const double *px = y + x_at(), *py = y + y_at();
  out.reset(temperature_at(), capacity_, ledger_at() + ledger_heat_walls);
  for (int p = 0, np = pp_.size(); p < np; ++p)
    if (const double h = pair_conductance(px, py, p); h != 0) out.add_link(pp_.i[p], pp_.j[p], h);
  wall_geometry(t, y, event_a_, event_b_);
  for (int p = 0, np = pw_.size(); p < np; ++p) {
    int wall = 0;
    if (const double h = wall_conductance(px, py, event_a_, event_b_, p, wall); h != 0) out.add_link(pw_.i[p], -1, h);
  }
  return true;
}

std::vector<ConductanceLink> DemSystem::conduction_links(double t, const double* y) const {
  std::vector<ConductanceLink> links;
  const double *px = y + x_at(), *py = y + y_at();
  for (int p = 0; p < pp_.size(); ++p)
    if (const double h = pair_conductance(px, py, p); h > 0) links.push_back({pp_.i[p], pp_.j[p], h});
  std::vector<Vec2> a, b;
  wall_geometry(t, y, a, b);
  for (int p = 0; p < pw_.size(); ++p) {
    int wall = 0;
    if (const double h = wall_conductance(px, py, a, b, p, wall); h > 0) links.push_back({pw_.i[p], -1 - wall, h});
  }
  return links;
}

}  // namespace kiln
