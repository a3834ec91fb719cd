// Normal contact force laws: pure functions of the overlap, the approach speed and the pair law.
//
// Every normal model has the form F_n = k delta^p + c delta^q d(delta)/dt (repulsive positive),
// one struct each with its source: contact/linear_spring.h (p = 1, q = 0) and
// contact/hertz_spring.h (p = 3/2, q = 1/4). The dashpot is c = beta sqrt(m_eff k), beta found
// from the restitution (restitution_damping). `with_normal_model` is the one place that turns a
// NormalModel into its struct: everything that depends on the model asks through it, so a new
// model is its struct, a case there and a row of contact/model_table.cpp.
#pragma once
#include <cmath>
#include <type_traits>

#include "contact/contact_law.h"
#include "contact/hertz_spring.h"
#include "contact/linear_spring.h"

namespace kiln::contact {

// Calls f with the struct of `model`. On a contact's path this costs what a test of a flag does:
// the case is inlined into each caller, and the switch has no default, so a model without a case
// is a compiler warning (-Wswitch), and no other value exists (the enum is only ever read from
// the model table).
template <class F>
[[gnu::always_inline]] inline decltype(auto) with_normal_model(NormalModel model, F&& f) {
  switch (model) {
    case NormalModel::linear:
      return f(LinearSpring{});
    case NormalModel::hertz:
      return f(HertzSpring{});
  }
  __builtin_unreachable();
}

struct NormalLaw {
  double k = 0;       // stiffness: N/m (linear) or N/m^1.5 (Hertz)
  double c = 0;       // dashpot: N s/m (linear) or N s/m^1.25 (Hertz)
  NormalModel model = NormalModel::linear;
  bool tension = true;  // false: no attractive force (F_n clamped at 0)
};

// The law with its model fixed to M's (M = void: the law's own): in a loop compiled for one model
// the model's switch in every function below folds away.
template <class M>
[[gnu::always_inline]] inline NormalLaw with_model_of(NormalLaw law) {
  if constexpr (!std::is_void_v<M>) law.model = M::model;
  return law;
}
// Normal force magnitude on the pair (positive pushes the bodies apart). `overlap` > 0.
[[gnu::always_inline]] inline double normal_force(const NormalLaw& law, double overlap, double approach_speed) {
  const double f =
      with_normal_model(law.model, [&](auto m) { return m.force(law.k, law.c, overlap, approach_speed); });
  return (!law.tension && f < 0) ? 0.0 : f;
}

// The same law for a contact whose state is located by contact events (ContactList::active):
// `pulling` is locked for the step, true once the law's force k delta^p + c delta^q v turned
// negative while the bodies overlapped (an event), so that no step straddles the cut at zero of a
// law without tension. Pressing, the law itself, also where the stages overshoot the pull's start
// or the release (a spring continued past separation: smooth through it); pulling, the law's pull
// with tension, else 0.
[[gnu::always_inline]] inline double located_normal_force(const NormalLaw& law, double overlap, double approach_speed, bool pulling) {
  const double f =
      with_normal_model(law.model, [&](auto m) { return m.force(law.k, law.c, overlap, approach_speed); });
  return pulling && !law.tension ? 0.0 : f;
}

// The normal load that carries the Coulomb and rolling caps (N): the compressive force, never a
// pull. A located contact (located_normal_force) carries its law's force while pressing, also
// where stages overshoot the pull's start or the release (negative there: the caps close through
// it as smoothly as the force does), and nothing while pulling. Cut at zero inside a step, the
// cap had a kink there, which the stages of a step that ends at a located release straddle (their
// states miss it by their stage errors): Sayfy-Aburub on the squeezed disc measured 2.9 to 3.7
// instead of 4, at step sizes where a release fell so.
[[gnu::always_inline]] inline double cap_load(double force, bool located, bool pulling) {
  return located ? (pulling ? 0.0 : force) : std::fmax(force, 0.0);
}

// What the normal force `force` carries beyond the conservative spring: the dashpot's part (N).
[[gnu::always_inline]] inline double dashpot_force(const NormalLaw& law, double overlap, double force) {
  return force - with_normal_model(law.model, [&](auto m) { return m.spring(law.k, overlap); });
}

// Power the normal force turns into heat: what it does beyond the conservative spring,
// (F_n - k delta^p) d(delta)/dt. Equals c delta^q v^2 while the force is not clamped.
[[gnu::always_inline]] inline double normal_dissipation(const NormalLaw& law, double overlap, double approach_speed, double force) {
  return dashpot_force(law, overlap, force) * approach_speed;
}

// Elastic energy stored in the normal spring (J): the integral of k delta^p over the overlap.
inline double normal_elastic_energy(const NormalLaw& law, double overlap) {
  return with_normal_model(law.model, [&](auto m) { return m.energy(law.k, overlap); });
}

// Linear(ised) normal stiffness dF/d(overlap) of the spring (N/m): the tangential and rolling
// springs scale with it.
[[gnu::always_inline]] inline double stiffness_slope(const NormalLaw& law, double overlap) {
  return with_normal_model(law.model, [&](auto m) { return m.slope(law.k, overlap); });
}

// d/dt of stiffness_slope at approach speed `speed` (N/(m s)): how fast the springs that scale with
// it stiffen (contact/stick_slip.h).
[[gnu::always_inline]] inline double stiffness_slope_rate(const NormalLaw& law, double overlap, double speed) {
  return with_normal_model(law.model, [&](auto m) { return m.slope_rate(law.k, overlap, speed); });
}

// delta^q: how the dashpot (normal and tangential) grows with the overlap.
[[gnu::always_inline]] inline double dashpot_scale(const NormalLaw& law, double overlap) {
  return with_normal_model(law.model, [&](auto m) { return m.dashpot_scale(overlap); });
}

// Whether the normal force jumps as a contact begins (a dashpot already pushing at zero overlap).
inline bool force_jumps_at_touch(NormalModel model) {
  return with_normal_model(model, [](auto m) { return m.force_jumps_at_touch; });
}

// How long a contact of effective mass m_eff lasts when it starts at `speed` (s).
inline double contact_duration(const NormalLaw& law, double m_eff, double speed) {
  return with_normal_model(law.model, [&](auto m) { return m.contact_duration(law.k, law.c, m_eff, speed); });
}

// The contact's fastest angular frequency (1/s) in an impact at `speed`: central differences are
// stable on it for dt < 2 / omega.
inline double limiting_frequency(const NormalLaw& law, double m_eff, double speed) {
  return with_normal_model(law.model, [&](auto m) { return m.limiting_frequency(law.k, law.c, m_eff, speed); });
}

// beta such that c = beta sqrt(m_eff k) gives restitution e for the model's form: the model's
// closed form where it has one (linear with tension: beta = 2 zeta), otherwise (Hertz, or no
// tension) found once by bisection on an accurate integration of the dimensionless collision
// u'' = -u^p - beta u^q u', u(0) = 0, u'(0) = 1, which is exact up to the quadrature error
// (relative 1e-7): e = -u'(t_end) at separation.
double restitution_damping(double e, NormalModel model, bool tension);

// Restitution that the dimensionless collision gives for a given beta (the inverse of the above).
double restitution_for_damping(double beta, NormalModel model, bool tension);

}  // namespace kiln::contact
