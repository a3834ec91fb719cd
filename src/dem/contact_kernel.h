// The contact kernel: one touching contact, particle-particle or particle-wall, from its
// kinematics to its forces and what they dissipate, with the history of its tangential and
// rolling springs. Included by the two contact stages, where it inlines into their loops.
//
// A wall is the other body with no lever arm and no mass of its own: its velocity at the contact
// point is in the relative velocity, its spin turns the rolling spring.
#pragma once
#include <cmath>

#include "contact/in_series.h"
#include "src/dem/dem_system.h"

namespace kiln {

[[gnu::always_inline]] inline void DemSystem::forget(const ContactArrays& list, int p) {
  list.trial[p] = 0;
  if (list.path_rate) list.path_rate[p] = 0;
  if (list.mode) list.margin[2 * p] = list.margin[2 * p + 1] = 0;  // nothing to switch: holds
  if (list.rolling) list.trial_roll[p] = 0;
  list.trial_frame[p] = {};
}

inline DemSystem::PairMasses DemSystem::pair_masses(int i, int j) const {
  if (j < 0) return {mass_[i], inertia_[i] + mass_[i] * radius_[i] * radius_[i], radius_[i], inertia_[i]};
  const double ri = inertia_[i] + mass_[i] * radius_[i] * radius_[i];
  const double rj = inertia_[j] + mass_[j] * radius_[j] * radius_[j];
  return {contact::in_series(mass_[i], mass_[j]), contact::in_series(ri, rj), contact::in_series(radius_[i], radius_[j]),
          contact::in_series(inertia_[i], inertia_[j])};
}

inline contact::TangentialLaw DemSystem::tangential_law(const ContactCoefficients& lf, const contact::NormalLaw& nl,
                                                        double overlap) const {
  return contact::tangential_law(nl, overlap, lf.law.tangential_stiffness_ratio, lf.law.tangential_damping_ratio,
                                lf.law.friction);
}

inline contact::RollingLaw DemSystem::rolling_law(const ContactCoefficients& lf, const contact::NormalLaw& nl,
                                                  double overlap, const PairMasses& pm, double load) const {
  return contact::rolling_law(lf.law.rolling_model, lf.law.rolling_friction, contact::stiffness_slope(nl, overlap),
                              pm.r_eff, pm.inertia, pm.spin_inertia, pm.m_eff, lf.law.rolling_damping_ratio, load);
}

// A capped element (element e of list: 2p tangential, 2p + 1 rolling) in its locked mode, leaving
// its event function and trial force for the event search (contact/stick_slip.h).
[[gnu::always_inline]] inline contact::CappedSpringResult DemSystem::locked(const ContactArrays& list, int e, double k,
                                                                            double c, double limit, double spring,
                                                                            double rate, const contact::CapRates& rates) {
  const contact::CappedSpringResult r = contact::locked_capped_spring(k, c, limit, spring, rate, list.mode[e]);
  list.margin[e] = contact::cap_margin(k, c, limit, spring, r.spring, rate, list.mode[e], rates);
  list.pull[e] = -k * spring - c * rate;
  return r;
}

// The normal force, then (with history) the tangential and rolling springs: their trial values
// are the committed ones plus what the contact points moved since the committed frame (springs in
// the state: plus the slip path the integrator advanced since the last accepted step). Inlined
// into each contact loop: called out of line it cost a call and a round trip of its arguments
// through memory per contact. Compiled for a loop's normal model M (void: each law's own) and
// for lists that may carry history (History) or never do.
template <bool History, class M>
[[gnu::always_inline]] inline DemSystem::ContactForces DemSystem::contact(const ContactArrays& list, int p,
                                                                          const ContactKinematics& c) const {
  ContactForces f;
  const double nx = c.frame.nx, ny = c.frame.ny;
  const double vn = c.rv.x * nx + c.rv.y * ny;      // approach speed
  const double drift = -c.rv.x * ny + c.rv.y * nx;  // the relative velocity along t
  const ContactCoefficients& lf = laws_[list.law[p]];
  const contact::NormalLaw nl = contact::with_model_of<M>(lf.normal_law_of(list.k[p], list.c[p]));
  // Located by contact events: the acting state, pressing or pulling, is locked for the step.
  const bool located = list.active != nullptr;
  const bool pulling = located && list.active[p] == 3;
  const double fn = located ? contact::located_normal_force(nl, c.overlap, vn, pulling)
                            : contact::normal_force(nl, c.overlap, vn);
  if (list.load_margin) {
    // The pull's start as an event: the law's force while pressing, its negation while pulling.
    // Without a dashpot the force reaches 0 only at separation, an event of its own; with
    // tension and no cap to carry, the pull changes nothing.
    const bool cut = nl.c > 0 && (!nl.tension || list.mode);
    const double law_force = pulling && !nl.tension ? contact::located_normal_force(nl, c.overlap, vn, false) : fn;
    list.load_margin[p] = cut ? (pulling ? -law_force : law_force) : 1.0;
  }
  f.damping_power = contact::normal_dissipation(nl, c.overlap, vn, fn);
  f.dashpot = contact::dashpot_force(nl, c.overlap, fn);  // damping_power = dashpot vn
  const bool history = History && list.history;
  if (history && (lf.tangential || lf.rolling)) {
    const contact::ContactFrame& from = list.frame[p];
    const bool known = from.known();  // a contact that began in this step starts unstretched
    // With stick and slip located: how fast the caps and the stiffnesses move.
    contact::CapRates rates;
    double load = 0;  // the caps' load where the modes are locked
    if (list.mode) {
      load = contact::cap_load(fn, true, pulling);
      const double slope = contact::stiffness_slope(nl, c.overlap);
      if (slope > 0) rates.growth = contact::stiffness_slope_rate(nl, c.overlap, vn) / slope;
      if (load != 0) rates.normal = slope * vn / load;
    }
    if (lf.tangential) {
      const double slip_speed = drift + c.w_i * c.arm_i + c.w_other * c.arm_other;
      const contact::TangentialLaw law = tangential_law(lf, nl, c.overlap);
      double trial = 0;
      if (list.stage_path) {
        trial = list.spring[p] + (list.stage_path[p] - list.path[p]);
        list.path_rate[p] = slip_speed;
      } else if (known) {
        trial = list.spring[p] +
                contact::tangential_displacement(from, c.frame, c.arm_then, c.arm_i, c.spun_i, c.spun_other);
      }
      contact::TangentialResult t;
      if (list.mode) {
        const contact::CappedSpringResult e =
            locked(list, 2 * p, law.k, law.c, law.mu * load, trial, slip_speed, rates);
        t = {e.force, e.spring, e.slipping};
      } else {
        t = contact::tangential_force(law, trial, slip_speed, fn);
      }
      list.trial[p] = t.spring;
      f.tangential = t.force;
      f.work_rate -= t.force * slip_speed;
    } else {
      if (list.path_rate) list.path_rate[p] = 0;
      if (list.mode) list.margin[2 * p] = 0;
    }
    if (lf.rolling) {
      const double relative_spin = c.w_i - c.w_other;
      const contact::RollingLaw law = rolling_law(lf, nl, c.overlap, pair_masses(c.i, c.j),
                                                     list.mode ? load : contact::cap_load(fn, false, false));
      const double trial = known ? list.roll[p] + (c.spun_i - c.spun_other) : 0.0;
      contact::RollingResult r;
      if (list.mode) {
        const contact::CappedSpringResult e = locked(list, 2 * p + 1, law.k, law.c, law.limit, trial, relative_spin, rates);
        r = {e.force, e.spring, e.slipping};
      } else {
        r = contact::rolling_torque(law, trial, relative_spin);
      }
      list.trial_roll[p] = r.spring;
      f.couple = r.torque;
      f.work_rate -= r.torque * relative_spin;
    } else if (list.mode) {
      list.margin[2 * p + 1] = 0;
    }
    // Field by field: a struct copy through the stack stalled store forwarding (15 % of a run).
    contact::ContactFrame& to = list.trial_frame[p];
    to.nx = c.frame.nx;
    to.ny = c.frame.ny;
    to.rho_t = c.frame.rho_t;
    to.rho_n = c.frame.rho_n;
  } else if (history) {
    forget(list, p);
  }
  set_resultant(f, fn, nx, ny);
  return f;
}

}  // namespace kiln
