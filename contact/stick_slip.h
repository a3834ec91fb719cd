// Stick and slip located: a capped spring (contact/capped_spring.h) whose mode is fixed for a step
// of a method that locates contact events, with the event function that says when it ends.
//
// Within a step the element either sticks, F = -k s - c v without a cap (continued past the cap
// until the switch is located), or slips, F = m L with m = +-1 the sign the trial force had when it
// reached the cap. A step whose stages straddled the switch would integrate a kink at second
// order at best (stages on either side of it see different force laws); with the switch located
// and the step restarted there, every stage sees one smooth law and the table keeps its order.
//
// The event functions are positive while the locked mode holds:
//  - stick: L - |k s + c v|, the margin to the Coulomb (or rolling) limit. Its zero is the
//    issue's |k_t xi + c_t v_t| - mu F_n = 0.
//  - slip: while the force the element would carry if it stuck exceeds the cap, and where it is
//    on the cap, while it would leave the cap (cap_margin below).
// Both are exact for the linear spring without dashpot (the matrix's pair rows), where the stick
// margin's zero is where the contact starts to slip and the slip function's is where it sticks.
#pragma once
#include <cmath>

#include "contact/capped_spring.h"

namespace kiln::contact {

// How fast a contact's cap and stiffness move (per second): `growth` = (dk/dt) / k, the same for
// every spring that scales with the normal stiffness; `normal` = (dF_n/dt) / F_n from the elastic
// part of the cap's load (contact/normal_force.h cap_load; 0 where the load is 0), so
// dL/dt = normal L.
struct CapRates {
  double growth = 0;
  double normal = 0;
};

// The element with its mode locked: `mode` 0 sticks, +-1 slips with force +-limit (the spring then
// shortened to the cap as in capped_spring, never lengthened).
[[gnu::always_inline]] inline CappedSpringResult locked_capped_spring(double k, double c, double limit, double spring,
                                                                      double rate, int mode) {
  CappedSpringResult r;
  r.spring = spring;
  if (mode == 0) {
    r.force = -k * spring - c * rate;
    return r;
  }
  r.force = mode * limit;
  r.slipping = true;
  if (k * std::abs(spring) > limit || limit == 0) r.spring = k > 0 ? std::copysign(limit / k, spring) : 0.0;
  return r;
}

// The event function of the locked element (above); `spring` is the trial spring (before the cap)
// and `held` the one locked_capped_spring returned. Positive while the mode holds.
//  - stick: the margin L - |k s + c v|.
//  - slip: the stick force's excess m (-k s - c v) - L while it is positive; with the spring on
//    the cap it is -m c v (exact: not k (L / k) - L, whose rounding would decide), the dashpot
//    pulling the way of the force. Where the excess is gone (always, for an element without
//    dashpot, whose spring on the cap carries exactly L) the rates decide: slip goes on while the
//    stick force would leave the cap faster than the cap moves, m dF/dt - dL/dt >= 0 with
//    dF/dt = -(dk/dt s + k v). That leaves out c dv/dt (the accelerations are not known in the
//    contact loop), which errs towards slip where v turns: an element that would stick there
//    slips on until its spring's rate agrees, and no switch is undone at the instant it is made.
[[gnu::always_inline]] inline double cap_margin(double k, double c, double limit, double spring, double held,
                                                double rate, int mode, const CapRates& rates) {
  if (mode == 0) return limit - std::abs(k * spring + c * rate);
  const double excess = held != spring || limit == 0 ? -mode * c * rate : -mode * (k * held + c * rate) - limit;
  if (excess > 0) return excess;
  if (!(k > 0)) return excess;  // a bare dashpot: its excess alone decides
  return -mode * k * (rates.growth * held + rate) - rates.normal * limit;
}
}  // namespace kiln::contact
