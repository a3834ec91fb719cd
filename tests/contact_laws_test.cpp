// The contact laws as pure functions: hand-computed values, the restitution inversion, and the
// Coulomb cap. No world needed.
#include <catch2/catch.hpp>
#include <cmath>

#include "contact/normal_force.h"
#include "contact/tangential_force.h"

using namespace kiln::contact;

TEST_CASE("linear normal force is k delta + c v and clamps only when tension is forbidden", "[contact]") {
  const NormalLaw law{6000, 0.5, false, true};
  CHECK(normal_force(law, 1e-4, 0.2) == Approx(6000 * 1e-4 + 0.5 * 0.2));
  CHECK(normal_force(law, 1e-5, -1.0) == Approx(0.06 - 0.5));  // attractive at the end of a contact
  const NormalLaw no_tension{6000, 0.5, false, false};
  CHECK(normal_force(no_tension, 1e-5, -1.0) == 0.0);
  CHECK(normal_elastic_energy(law, 1e-4) == Approx(0.5 * 6000 * 1e-8));
}

TEST_CASE("Hertz normal force is k delta^1.5 + c delta^0.25 v with energy 2/5 k delta^2.5", "[contact]") {
  const NormalLaw law{2e9, 30, true, true};
  const double d = 4e-6, v = 0.1;
  CHECK(normal_force(law, d, v) == Approx(2e9 * std::pow(d, 1.5) + 30 * std::pow(d, 0.25) * v));
  CHECK(normal_elastic_energy(law, d) == Approx(0.4 * 2e9 * std::pow(d, 2.5)));
  // The dissipated power is what the force does beyond the spring.
  CHECK(normal_dissipation(law, d, v, normal_force(law, d, v)) == Approx(30 * std::pow(d, 0.25) * v * v));
}

TEST_CASE("restitution damping: closed form for the linear law agrees with the collision integration", "[contact]") {
  for (double e : {0.1, 0.3, 0.5, 0.8, 0.95}) {
    const double beta = restitution_damping(e, false, true);
    const double l = std::log(e);
    CHECK(beta == Approx(-2 * l / std::sqrt(M_PI * M_PI + l * l)));
    CHECK(restitution_for_damping(beta, false, true) == Approx(e).epsilon(1e-5));
  }
}

TEST_CASE("restitution damping inverts exactly for Hertz and for clamped laws", "[contact]") {
  for (bool hertz : {false, true})
    for (bool tension : {false, true})
      for (double e : {0.2, 0.5, 0.9}) {
        const double beta = restitution_damping(e, hertz, tension);
        CHECK(restitution_for_damping(beta, hertz, tension) == Approx(e).epsilon(1e-6));
      }
  CHECK(restitution_damping(1.0, true, true) == 0.0);
  // Forbidding tension ends the contact earlier, with less time to dissipate: more damping needed.
  CHECK(restitution_damping(0.5, false, false) > restitution_damping(0.5, false, true));
}

TEST_CASE("contact durations: linear pi/omega_d, Hertz 2.87 (m^2/(k^2 v))^(1/5)", "[contact]") {
  const double m = 1e-3, k = 1e4;
  CHECK(linear_contact_duration(k, 0, m) == Approx(M_PI * std::sqrt(m / k)));
  CHECK(linear_contact_duration(k, 2 * std::sqrt(k * m), m) == INFINITY);  // critically damped
  // Against a direct integration of the undamped Hertz collision in dimensionless units (t* = 3.2181).
  CHECK(hertz_contact_duration(1, 1, 1) == Approx(2.868265699));
}

TEST_CASE("tangential spring sticks below mu Fn and slides at the Coulomb limit", "[contact]") {
  const TangentialLaw law{1000, 0.1, 0.5};
  // Sticking: elongation grows by v dt, force -k s - c v, dissipation only in the dashpot.
  auto stick = tangential_force(law, 1e-5, 0.01, 1e-4, 1e4, 10.0);
  CHECK_FALSE(stick.sliding);
  CHECK(stick.spring == Approx(1e-5 + 1e-6));
  CHECK(stick.force == Approx(-1000 * 1.1e-5 - 0.1 * 0.01));
  // Sliding: force capped at mu Fn, the spring alone set to carry it.
  auto slide = tangential_force(law, 1e-2, 0.5, 1e-4, 1e4, 1.0);
  CHECK(slide.sliding);
  CHECK(std::abs(slide.force) == Approx(0.5));
  CHECK(-law.k * slide.spring == Approx(slide.force));
  // Slip power minus stored spring energy: the ledger's dissipation is never negative when sliding.
  CHECK(slide.dissipation > 0);
  // A tensile normal force carries no friction.
  CHECK(tangential_force(law, 1e-3, 0.1, 1e-4, 1e4, -2.0).force == 0.0);
}

TEST_CASE("rolling resistance opposes the relative spin with mu_r R* Fn", "[contact]") {
  CHECK(rolling_torque(0.1, 1e-3, 2.0, 5.0) == Approx(-2e-4));
  CHECK(rolling_torque(0.1, 1e-3, 2.0, -5.0) == Approx(2e-4));
  CHECK(rolling_torque(0.1, 1e-3, 2.0, 0.0) == 0.0);
}
