// The linear spring-dashpot normal model (CSIRO [csiro-dem-spring-dashpot.txt]: F_n = -k dx + C v_n;
// thesis eq. for the normal spring K with dashpot C): F_n = k delta + c d(delta)/dt, the form
// k delta^p + c delta^q d(delta)/dt of contact/normal_force.h with p = 1, q = 0. k in N/m, c in
// N s/m, delta the overlap (m), d(delta)/dt the approach speed (m/s), forces in N.
// A model of contact/normal_force.h: its functions are selected there, by `with_normal_model`.
#pragma once
#include <cmath>
#include <optional>

#include "contact/contact_law.h"

namespace kiln::contact {

struct LinearSpring {
  static constexpr NormalModel model = NormalModel::linear;
  static double force(double k, double c, double overlap, double speed) { return k * overlap + c * speed; }
  static double spring(double k, double overlap) { return k * overlap; }
  // Elastic energy stored in the spring: k delta^2 / 2.
  static double energy(double k, double overlap) { return 0.5 * k * overlap * overlap; }
  // dF/d(delta) of the spring, which the tangential and rolling springs scale with: k.
  static double slope(double k, double /*overlap*/) { return k; }
  // Its rate as the overlap changes at `speed`: 0.
  static double slope_rate(double /*k*/, double /*overlap*/, double /*speed*/) { return 0.0; }
  // delta^q, the dashpot's dependence on the overlap (the tangential dashpot's too): 1.
  static double dashpot_scale(double /*overlap*/) { return 1.0; }
  // A dashpot with q = 0 pushes at first touch: the force jumps as a contact begins.
  static constexpr bool force_jumps_at_touch = true;

  // The pair's k: the contact's or the materials' mixed stiffness, whatever the radii.
  static double stiffness(const ContactLaw& law, double /*r_eff*/) { return law.stiffness; }

  // Contact duration with dashpot: pi / sqrt(k/m - (c/(2m))^2), whatever the impact speed.
  static double contact_duration(double k, double c, double m_eff, double /*speed*/) {
    const double w2 = k / m_eff - (c / (2 * m_eff)) * (c / (2 * m_eff));
    return w2 > 0 ? M_PI / std::sqrt(w2) : INFINITY;
  }
  // Central-difference limit of a damped oscillator: 2 (sqrt(1 + zeta^2) - zeta) / omega, written
  // as 2 / omega' with omega' = omega / (sqrt(1 + zeta^2) - zeta), omega = sqrt(k/m_eff).
  static double limiting_frequency(double k, double c, double m_eff, double /*speed*/) {
    const double omega = std::sqrt(k / m_eff);
    const double zeta = c / (2 * std::sqrt(m_eff * k));
    return omega / (std::sqrt(1 + zeta * zeta) - zeta);
  }
  // With tension the dimensionless collision is a damped oscillator, whose restitution is exact:
  // beta = 2 zeta with zeta = -ln e / sqrt(pi^2 + ln^2 e). Without, it is integrated (normal_force.h).
  static std::optional<double> closed_form_damping(double e, bool tension) {
    if (!tension) return std::nullopt;
    const double l = std::log(e);
    return -2 * l / std::sqrt(M_PI * M_PI + l * l);
  }
};

}  // namespace kiln::contact
