// The contact frame: where a contact is, seen from particle i, at one instant. The tangential and
// rolling springs are measured from the frame of the last accepted step, so that a spring's
// elongation at any later state is a function of that state (contact/tangential_force.h).
//
// Geometry (2D): n is the unit contact normal from i's centre towards the other body, t = perp(n)
// = (-n_y, n_x). rho = x_i - X, X a point fixed on the other body (its centre; for a wall the
// segment's first end point, which moves with the wall). The contact point lies on the line of
// centres at the lever arm `arm` from i's centre.
//
// The slip rate of the contact points is v_t = (v_i - v_X) . t + (omega_i - omega_o) arm
// - omega_o (rho . n), and since rho' . t = d(rho . t)/dt + phi' (rho . n) (phi the angle of n):
//   v_t = d(rho . t)/dt + (phi' - omega_o) (rho . n) + (omega_i - omega_o) arm.
// Its time integral from frame a to frame b is therefore
//   Delta xi = Delta(rho . t) + int (rho . n) d(phi - theta_o) + int arm d(theta_i - theta_o),
// exact when rho . n and the arm do not change or the angles they multiply do not (a disc on a
// flat wall, fixed or moving: the order of any integrator is kept), and otherwise evaluated with
// the trapezoidal rule in the two frames: second order in the step (two discs whose contact line
// turns while their overlap changes). The spring is the incremental one of Cundall and Strack
// ("A discrete numerical model for granular assemblies", Geotechnique 29, 1979), integrated
// along the path instead of per step. The angles turned come from the particles' committed
// angles (dem_system.cpp), so a frame is four numbers.
#pragma once
#include <cmath>

namespace kiln::contact {

struct ContactFrame {
  double nx = 0, ny = 0;        // contact normal, unit, from i towards the other body; 0: no frame
  double rho_t = 0, rho_n = 0;  // i's centre relative to the other body's fixed point, on t and n (m)
  bool known() const { return (nx != 0) | (ny != 0); }
};

// The angle from unit vector a to unit vector b, given cross(a, b) = sin and dot(a, b) = cos.
// Within a step contact normals turn by far less than 0.01 rad (small_turn), where the odd series
// of asin to x^7 is exact to double precision (the next term is below 1e-19 x); atan2 elsewhere.
// atan2 in the force loop cost 20 % of a run; the batched contact loop takes the series for all
// and redoes the rare others.
[[gnu::always_inline]] inline bool small_turn(double sine, double cosine) { return (cosine > 0) & (std::abs(sine) < 1e-2); }
[[gnu::always_inline]] inline double small_turn_angle(double sine) {
  const double x2 = sine * sine;
  return sine * (1 + x2 * (1.0 / 6 + x2 * (3.0 / 40 + x2 * (15.0 / 336))));
}
[[gnu::always_inline]] inline double turn_angle(double sine, double cosine) {
  return small_turn(sine, cosine) ? small_turn_angle(sine) : std::atan2(sine, cosine);
}
// The sine and cosine of the angle from a's normal to b's.
[[gnu::always_inline]] inline double turn_sine(const ContactFrame& a, const ContactFrame& b) {
  return a.nx * b.ny - a.ny * b.nx;
}
[[gnu::always_inline]] inline double turn_cosine(const ContactFrame& a, const ContactFrame& b) {
  return a.nx * b.nx + a.ny * b.ny;
}

// Relative tangential displacement of the contact points from frame a to frame b (m), along b's
// t, the normal having turned by `turned` (rad). `arm_a`, `arm_b`: i's lever arms in the two
// frames; `spun_i`, `spun_other`: how far i and the other body turned from a to b (rad).
[[gnu::always_inline]] inline double tangential_displacement(const ContactFrame& a, const ContactFrame& b, double turned,
                                                             double arm_a, double arm_b, double spun_i,
                                                             double spun_other) {
  return (b.rho_t - a.rho_t) + 0.5 * (a.rho_n + b.rho_n) * (turned - spun_other) +
         0.5 * (arm_a + arm_b) * (spun_i - spun_other);
}
[[gnu::always_inline]] inline double tangential_displacement(const ContactFrame& a, const ContactFrame& b, double arm_a,
                                                             double arm_b, double spun_i, double spun_other) {
  return tangential_displacement(a, b, turn_angle(turn_sine(a, b), turn_cosine(a, b)), arm_a, arm_b, spun_i,
                                 spun_other);
}

// Lever arms of two discs in contact: one contact point on the line of centres, in the middle of
// the overlap, so both arms end at the same point (r_i - delta/2 and r_j - delta/2 add up to the
// distance of the centres). Equal and opposite forces at one point keep the total angular
// momentum exactly; full radii as arms would change it by F_t delta per unit time.
inline double pair_arm(double radius, double overlap) { return radius - 0.5 * overlap; }

}  // namespace kiln::contact
