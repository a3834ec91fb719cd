// The Hertz normal model with the Tsuji et al. (1992) dashpot: F_n = k delta^3/2 + c delta^1/4
// d(delta)/dt, the form of contact/normal_force.h with p = 3/2, q = 1/4, and k = 4/3 E* sqrt(R*),
// 1/E* = (1-nu_i^2)/E_i + (1-nu_j^2)/E_j, 1/R* = 1/r_i + 1/r_j (Nguyen et al. 2009, section on
// Hertz contact [nguyen2009-friction-heat-dem.txt]). k in N/m^1.5, c in N s/m^1.25. With q = 1/4
// the restitution does not depend on the impact speed, so the dashpot's beta is a function of e
// alone. A model of contact/normal_force.h: its functions are selected there, by `with_normal_model`.
#pragma once
#include <cmath>
#include <optional>

#include "contact/contact_law.h"

namespace kiln::contact {

struct HertzSpring {
  static constexpr NormalModel model = NormalModel::hertz;
  static double force(double k, double c, double overlap, double speed) {
    const double root = std::sqrt(std::fmax(overlap, 0.0));  // continued by 0 past separation
    return k * overlap * root + c * std::sqrt(root) * speed;
  }
  // Every function of the overlap is continued by 0 past separation: with contact events an acting
  // contact keeps its law for the rest of a step after its release (delta^1/2 of a negative overlap
  // was NaN, and a damped Hertz bounce under erk4 with events stopped on it at the release).
  static double spring(double k, double overlap) { return k * overlap * std::sqrt(std::fmax(overlap, 0.0)); }
  // Elastic energy stored in the spring: 2/5 k delta^(5/2).
  static double energy(double k, double overlap) {
    return 0.4 * k * overlap * overlap * std::sqrt(std::fmax(overlap, 0.0));
  }
  // dF/d(delta) of the spring, which the tangential and rolling springs scale with: 3/2 k delta^1/2.
  static double slope(double k, double overlap) { return 1.5 * k * std::sqrt(std::fmax(overlap, 0.0)); }
  // Its rate as the overlap changes at `speed`: 3/4 k delta^-1/2 d(delta)/dt (0 at and past touch).
  static double slope_rate(double k, double overlap, double speed) {
    return overlap > 0 ? 0.75 * k * speed / std::sqrt(overlap) : 0.0;
  }
  // delta^q, the dashpot's dependence on the overlap (the tangential dashpot's too): delta^1/4.
  static double dashpot_scale(double overlap) { return std::sqrt(std::sqrt(std::fmax(overlap, 0.0))); }
  // The dashpot vanishes with the overlap: the force is continuous as a contact begins.
  static constexpr bool force_jumps_at_touch = false;

  // k = 4/3 E* sqrt(R*) for the pair's effective radius R* (a wall: the disc's radius).
  static double stiffness(const ContactLaw& law, double r_eff) {
    return 4.0 / 3.0 * law.effective_modulus * std::sqrt(r_eff);
  }

  // Contact duration for impact speed v (undamped): 2.94328 delta_max / v with
  // delta_max = (15 m* v^2 / (16 E* sqrt(R*)))^(2/5) (Johnson, Contact Mechanics, 1985, eqs. 11.23
  // and 11.24), rewritten for k = 4/3 E* sqrt(R*): delta_max = (5 m* v^2 / (4 k))^(2/5), so
  // t_c = 2.94328 (5/4)^(2/5) (m*^2 / (k^2 v))^(1/5) = 3.2181 (m*^2 / (k^2 v))^(1/5).
  // (Johnson's 2.87 belongs to the form with E* and R* written out, not to k.)
  static double contact_duration(double k, double /*c*/, double m_eff, double speed) {
    constexpr double hertz_time_constant = 2.9432752;  // 2 int_0^1 du / sqrt(1 - u^(5/2)) = (4/5) B(2/5, 1/2)
    return hertz_time_constant * std::pow(1.25 * m_eff / k, 0.4) * std::pow(speed, -0.2);
  }
  // The stiffest the spring gets in an impact at `speed`: its slope at the largest overlap,
  // delta_max = (5 m* v^2 / (4 k))^(2/5), as a frequency sqrt(slope / m*).
  static double limiting_frequency(double k, double /*c*/, double m_eff, double speed) {
    const double max_overlap = std::pow(1.25 * m_eff * speed * speed / k, 0.4);
    return std::sqrt(1.5 * k * std::sqrt(max_overlap) / m_eff);
  }
  // The dashpot's beta for a restitution has no closed form: it is integrated (normal_force.h).
  static std::optional<double> closed_form_damping(double /*e*/, bool /*tension*/) { return std::nullopt; }
};

}  // namespace kiln::contact
