// Normal contact force laws: pure functions of the overlap, the approach speed and the pair law.
//
// Both laws share one form, F_n = k delta^p + c delta^q d(delta)/dt (repulsive positive):
//  - linear spring-dashpot (CSIRO [csiro-dem-spring-dashpot.txt]: F_n = -k dx + C v_n; thesis
//    eq. for the normal spring K with dashpot C): p = 1, q = 0;
//  - Hertz with the Tsuji et al. (1992) dashpot: p = 3/2, q = 1/4, k = 4/3 E* sqrt(R*),
//    1/E* = (1-nu_i^2)/E_i + (1-nu_j^2)/E_j, 1/R* = 1/r_i + 1/r_j (Nguyen et al. 2009, section on
//    Hertz contact [nguyen2009-friction-heat-dem.txt]).
// The dashpot is c = beta sqrt(m_eff k). With q = 1/4 the restitution of a Hertz contact does not
// depend on the impact speed, so beta is a function of e alone (see restitution_damping).
#pragma once
#include <cmath>

namespace kiln::contact {

struct NormalLaw {
  double k = 0;       // stiffness: N/m (linear) or N/m^1.5 (Hertz)
  double c = 0;       // dashpot: N s/m (linear) or N s/m^1.25 (Hertz)
  bool hertz = false;
  bool tension = true;  // false: no attractive force (F_n clamped at 0)
};

// Normal force magnitude on the pair (positive pushes the bodies apart). `overlap` > 0.
inline double normal_force(const NormalLaw& law, double overlap, double approach_speed) {
  double f;
  if (law.hertz) {
    const double root = std::sqrt(std::fmax(overlap, 0.0));  // continued by 0 past separation
    f = law.k * overlap * root + law.c * std::sqrt(root) * approach_speed;
  } else {
    f = law.k * overlap + law.c * approach_speed;
  }
  return (!law.tension && f < 0) ? 0.0 : f;
}

// What the normal force `force` carries beyond the conservative spring: the dashpot's part (N).
inline double dashpot_force(const NormalLaw& law, double overlap, double force) {
  const double spring = law.hertz ? law.k * overlap * std::sqrt(overlap) : law.k * overlap;
  return force - spring;
}

// Power the normal force turns into heat: what it does beyond the conservative spring,
// (F_n - k delta^p) d(delta)/dt. Equals c delta^q v^2 while the force is not clamped.
inline double normal_dissipation(const NormalLaw& law, double overlap, double approach_speed, double force) {
  return dashpot_force(law, overlap, force) * approach_speed;
}

// Elastic energy stored in the normal spring: k delta^2/2 (linear), 2/5 k delta^(5/2) (Hertz).
inline double normal_elastic_energy(const NormalLaw& law, double overlap) {
  return law.hertz ? 0.4 * law.k * overlap * overlap * std::sqrt(overlap) : 0.5 * law.k * overlap * overlap;
}

// beta such that c = beta sqrt(m_eff k) gives restitution e for the law's form.
// Linear with tension: exact closed form, beta = 2 zeta with zeta = -ln e / sqrt(pi^2 + ln^2 e).
// Otherwise (Hertz, or no tension): found once by bisection on an accurate integration of the
// dimensionless collision u'' = -u^p - beta u^q u', u(0) = 0, u'(0) = 1, which is exact up to
// the quadrature error (relative 1e-7): e = -u'(t_end) at separation.
double restitution_damping(double e, bool hertz, bool tension);

// Restitution that the dimensionless collision gives for a given beta (the inverse of the above).
double restitution_for_damping(double beta, bool hertz, bool tension);

// Contact duration of the linear law with dashpot: pi / sqrt(k/m - (c/(2m))^2).
inline double linear_contact_duration(double k, double c, double m_eff) {
  const double w2 = k / m_eff - (c / (2 * m_eff)) * (c / (2 * m_eff));
  return w2 > 0 ? M_PI / std::sqrt(w2) : INFINITY;
}

// Hertz contact duration for impact speed v (undamped): 2.94328 delta_max / v with
// delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5) (Johnson, Contact Mechanics, 1985, eqs. 11.23
// and 11.24), rewritten for k = 4/3 E* sqrt(R*): delta_max = (5 m* v^2 / (4 k))^(2/5), so
// t_c = 2.94328 (5/4)^(2/5) (m*^2 / (k^2 v))^(1/5) = 3.2181 (m*^2 / (k^2 v))^(1/5).
// (Johnson's 2.87 belongs to the form with E* and R* written out, not to k.)
inline double hertz_contact_duration(double k, double m_eff, double v) {
  constexpr double hertz_time_constant = 2.9432752;  // 2 int_0^1 du / sqrt(1 - u^(5/2)) = (4/5) B(2/5, 1/2)
  return hertz_time_constant * std::pow(1.25 * m_eff / k, 0.4) * std::pow(v, -0.2);
}

}  // namespace kiln::contact
