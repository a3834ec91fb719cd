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
//  - slip: m dF/dt - dL/dt with the spring on the cap: slip goes on while the trial force the
//    spring would carry if it stuck grows at least as fast as the limit, and stick resumes where
//    it falls behind (for a spring without dashpot, where the slip speed reverses against the
//    cap's own motion). dF/dt = -(dk/dt s + k v) leaves out the dashpot's c dv/dt, which needs the
//    accelerations: with a dashpot the switch back to stick is located on the spring's rates alone.
// Both are exact for the linear spring without dashpot (the matrix's pair rows), where the stick
// margin's zero is where the contact starts to slip and the slip function's is where it sticks.
#pragma once
#include <cmath>

#include "contact/capped_spring.h"

namespace kiln::contact {

// How fast a contact's cap and stiffness move (per second): `growth` = (dk/dt) / k, the same for
// every spring that scales with the normal stiffness; `normal` = (dF_n/dt) / F_n from the elastic
// part of the normal force (0 without a compressive force), so dL/dt = normal L.
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

// The event function of the locked element (above); `spring` is the one locked_capped_spring
// returned. Positive while the mode holds.
[[gnu::always_inline]] inline double cap_margin(double k, double c, double limit, double spring, double rate, int mode,
                                                const CapRates& rates) {
  if (mode == 0) return limit - std::abs(k * spring + c * rate);
  if (!(k > 0)) return -mode * c * rate - limit;  // a bare dashpot: slips while its force exceeds the cap
  return -mode * k * (rates.growth * spring + rate) - rates.normal * limit;
}

}  // namespace kiln::contact
