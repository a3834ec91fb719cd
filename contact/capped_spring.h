// A spring with a dashpot in parallel, its force capped: the element behind both friction laws
// (tangential: force and elongation; rolling: torque and spring angle).
//
// Trial force -k s - c v; above the cap L the element slips and carries L. The cap only ever
// shortens the spring, to k |s| <= L (LIGGGHTS' tangential history model limits the spring the
// same way, Kloss et al., LIGGGHTS tangential_model_history.h), and never lengthens it: setting
// k |s| = L whenever the element slips would make the spring carry the dashpot's share too,
// storing energy that no force put in (on a grazing wall impact the ledger's friction dissipation
// went negative by 3.2e-6 J of 6.65e-6 J). With k |s| <= L the power the element takes,
// -F v, is never less than the rate its spring stores, k s v: what it dissipates never falls.
// Stick resumes without a jump, where |k s + c v| falls back to L.
#pragma once
#include <cmath>

namespace kiln::contact {

struct CappedSpringResult {
  double force = 0;   // -k s - c v, or +-L at the cap (N or N m)
  double spring = 0;  // the spring after the cap (m or rad)
  bool slipping = false;
};

// `spring`: the trial spring s of this state; `rate`: its rate v; `limit`: L >= 0. A cap of zero
// (no normal force) empties the spring: the contact holds nothing.
// Without a branch (selects), so that a loop over contacts can be vectorised.
[[gnu::always_inline]] inline CappedSpringResult capped_spring(double k, double c, double limit, double spring,
                                                               double rate) {
  // Every operand computed, then chosen: an operation inside a condition (it might raise a
  // floating-point exception) is not executed speculatively, and the loop would keep its branches.
  const double trial = -k * spring - c * rate;
  const bool capped = std::abs(trial) > limit;
  const bool shortened = capped & ((k * std::abs(spring) > limit) | (limit == 0));
  const double cap_length = limit / k;
  const double on_cap = k > 0 ? std::copysign(cap_length, spring) : 0.0;
  return {capped ? std::copysign(limit, trial) : trial, shortened ? on_cap : spring, capped};
}

}  // namespace kiln::contact
