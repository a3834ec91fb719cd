// Contact events: each candidate contact's overlap, and with friction or rolling resistance each
// spring's stick or slip, as event functions; the acting set and the modes locked within a step
// (integrators that locate contact onsets, releases and stick-slip switches).
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

// Each function is positive while the locked set holds: an acting contact's overlap, an idle
// one's negated overlap, then each capped element's margin, then each contact's load (pressing:
// its law's force; pulling: the negation), the last two from an evaluation of the state.
void DemSystem::event_functions(double t, const double* y, double* g) {
  const double *px = y + x_at(), *py = y + y_at();
  std::vector<Vec2>&a = event_a_, &b = event_b_;  // kept: event location runs every step
  wall_geometry(t, y, a, b);
  const int np = pp_.size(), nw = pw_.size();
  for (int p = 0; p < np; ++p) g[p] = pair_overlap(px, py, p) * (pp_.active[p] ? 1 : -1);
  for (int p = 0; p < nw; ++p) g[np + p] = wall_overlap(px, py, a, b, p) * (pw_.active[p] ? 1 : -1);
  if (!pp_.located && !pp_.load_events) return;
  // The margins come from the contact kernel: one evaluation here, at each trial end the search
  // looks at (its cost, an evaluation per step and per bisection, is in the README's report).
  // Contacts it does not evaluate (idle, or between two attached discs) hold.
  std::fill(pp_.load_margin.begin(), pp_.load_margin.end(), 1.0);
  std::fill(pw_.load_margin.begin(), pw_.load_margin.end(), 1.0);
  event_rates_.resize(state_size());
  derivative(t, y, event_rates_.data());
  double* next = g + np + nw;
  if (pp_.located) {
    next = std::copy(pp_.margin.begin(), pp_.margin.end(), next);
    next = std::copy(pw_.margin.begin(), pw_.margin.end(), next);
  }
  if (pp_.load_events) {
    next = std::copy(pp_.load_margin.begin(), pp_.load_margin.end(), next);
    std::copy(pw_.load_margin.begin(), pw_.load_margin.end(), next);
  }
}

void DemSystem::lock_contacts(double t, const double* y, const int* flips) {
  // After a located event the functions that stopped holding switch their contacts: a contact
  // starts or ends (its springs stick from there), an element slips the way its trial force
  // pulled at the event (the latest evaluation's) or sticks again. Contacts not known yet (the
  // start, new candidates) act where their overlap is positive, and stick.
  const double *px = y + x_at(), *py = y + y_at();
  std::vector<Vec2>&a = event_a_, &b = event_b_;  // kept: event location runs every step
  wall_geometry(t, y, a, b);
  const int np = pp_.size(), nw = pw_.size();
  const int modes = pp_.located ? 2 * (np + nw) : 0;
  auto lock = [&](ContactList& list, int count, int first_overlap, int first_mode, int first_load, auto overlap) {
    for (int p = 0; p < count; ++p) {
      const bool flipped = flips && flips[first_overlap + p];
      if (flipped) {
        list.active[p] = list.active[p] ? 0 : 1;  // a contact starts pressing
        if (list.located) list.mode[2 * p] = list.mode[2 * p + 1] = 0;
      }
      if (list.active[p] == 2) list.active[p] = overlap(p) > 0;
      if (!flips || flipped) continue;
      // A pull that starts or ends while the bodies overlap.
      if (list.load_events && flips[first_load + p] && list.active[p]) list.active[p] = list.active[p] == 3 ? 1 : 3;
      if (!list.located) continue;
      for (int e = 2 * p; e < 2 * p + 2; ++e)
        if (flips[first_mode + e]) list.mode[e] = list.mode[e] ? 0 : (list.pull[e] >= 0 ? 1 : -1);
    }
  };
  lock(pp_, np, 0, np + nw, np + nw + modes, [&](int p) { return pair_overlap(px, py, p); });
  lock(pw_, nw, np, np + nw + 2 * np, 2 * np + nw + modes, [&](int p) { return wall_overlap(px, py, a, b, p); });
}

}  // namespace kiln
