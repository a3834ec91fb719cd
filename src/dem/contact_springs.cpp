// The touching contacts linearised at a state: what the stability limit assembles into the
// scene's stiffness and damping (src/run/linearised_dynamics.h). Each slope comes from the same
// laws and coefficients as the force loops (contact_kernel.h), at the contact's own overlap.
#include "src/dem/contact_kernel.h"

namespace kiln {

std::vector<ContactSprings> DemSystem::contact_springs(double t, const double* y) const {
  std::vector<ContactSprings> out;
  const double *px = y + x_at(), *py = y + y_at();
  // The springs of a contact of law lf at this overlap, with its committed tangential and rolling
  // springs (entry p of `list`) telling whether it sticks.
  auto springs = [&](const ContactList& list, int p, double overlap, const PairMasses& pm, ContactSprings& s) {
    const ContactCoefficients& lf = laws_[list.law[p]];
    const contact::NormalLaw nl = lf.normal_law_of(list.k[p], list.c[p]);
    s.kn = contact::stiffness_slope(nl, overlap);
    s.cn = nl.c * contact::dashpot_scale(nl, overlap);
    if (!list.history) return;
    const double fn = contact::normal_force(nl, overlap, 0);
    const bool known = list.frame[p].known();
    if (lf.tangential) {
      const contact::TangentialLaw law = tangential_law(lf, nl, overlap);
      if (!(known && law.k * std::abs(list.spring[p]) >= law.mu * std::max(fn, 0.0))) {
        s.kt = law.k;
        s.ct = law.c;
      }
    }
    if (lf.rolling) {
      const contact::RollingLaw law = rolling_law(lf, nl, overlap, pm, contact::cap_load(fn, false, false));
      if (!(known && law.k * std::abs(list.roll[p]) >= law.limit)) {
        s.kr = law.k;
        s.cr = law.c;
      }
    }
  };
  for (int p = 0; p < pp_.size(); ++p) {
    const int i = pp_.i[p], j = pp_.j[p];
    const double overlap = pair_overlap(px, py, p);
    if (overlap <= 0 || (attached(i) && attached(j))) continue;
    const Vec2 d = separation(px, py, i, j);
    const double dist = radius_[i] + radius_[j] - overlap;
    ContactSprings s;
    s.i = i;
    s.j = j;
    s.normal = {d.x / dist, d.y / dist};
    s.arm_i = contact::pair_arm(radius_[i], overlap);
    s.arm_j = contact::pair_arm(radius_[j], overlap);
    springs(pp_, p, overlap, pair_masses(i, j), s);
    out.push_back(s);
  }
  std::vector<Vec2> a, b;
  wall_geometry(t, y, a, b);
  for (int p = 0; p < pw_.size(); ++p) {
    const int i = pw_.i[p];
    WallHit hit;
    if (attached(i) || !wall_hit(px, py, a, b, i, pw_.j[p], hit, false)) continue;
    ContactSprings s;
    s.i = i;
    s.j = -1 - scene_.segments[pw_.j[p]].wall;
    s.normal = hit.normal;
    s.arm_i = radius_[i];
    springs(pw_, p, hit.overlap, pair_masses(i, -1), s);
    out.push_back(s);
  }
  return out;
}

}  // namespace kiln
