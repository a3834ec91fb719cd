// Contact events: each candidate contact's overlap as an event function, and the acting set
// locked within a step (integrators that locate contact onsets and releases).
#include "src/dem/dem_system.h"

namespace kiln {

double DemSystem::pair_overlap(const double* px, const double* py, int p) const {
  const int i = pp_.i[p], j = pp_.j[p];
  const Vec2 d = separation(px, py, i, j);
  return radius_[i] + radius_[j] - std::hypot(d.x, d.y);
}

double DemSystem::wall_overlap(const double* px, const double* py, const std::vector<Vec2>& a,
                               const std::vector<Vec2>& b, int p) const {
  WallHit hit;
  // A vertex owned by the neighbouring segment is no contact of this one: always apart.
  return wall_hit(px, py, a, b, pw_.i[p], pw_.j[p], hit, true) ? hit.overlap : -radius_[pw_.i[p]];
}

void DemSystem::event_functions(double t, const double* y, double* g) const {
  const double *px = y + x_at(), *py = y + y_at();
  std::vector<Vec2>&a = event_a_, &b = event_b_;  // kept: event location runs every step
  wall_geometry(t, y, a, b);
  for (int p = 0; p < pp_.size(); ++p) g[p] = pair_overlap(px, py, p);
  for (int p = 0; p < pw_.size(); ++p) g[pp_.size() + p] = wall_overlap(px, py, a, b, p);
}

void DemSystem::lock_contacts(double t, const double* y, const int* flips) {
  // After a located event the root finder's directions decide (the overlap there is ~0);
  // contacts not known yet (the start, new candidates) act where their overlap is positive.
  const double *px = y + x_at(), *py = y + y_at();
  std::vector<Vec2>&a = event_a_, &b = event_b_;  // kept: event location runs every step
  wall_geometry(t, y, a, b);
  for (int p = 0; p < pp_.size(); ++p) {
    if (flips && flips[p]) pp_.active[p] = flips[p] > 0;
    if (pp_.active[p] == 2) pp_.active[p] = pair_overlap(px, py, p) > 0;
  }
  for (int p = 0; p < pw_.size(); ++p) {
    const int k = pp_.size() + p;
    if (flips && flips[k]) pw_.active[p] = flips[k] > 0;
    if (pw_.active[p] == 2) pw_.active[p] = wall_overlap(px, py, a, b, p) > 0;
  }
}

}  // namespace kiln
