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
// turns while their overlap changes). The source of the construction: the incremental spring of
// Cundall and Strack (1979, Geotechnique 29, eq. 6) integrated along the path instead of per step.
#pragma once
#include <cmath>

namespace kiln::contact {

struct ContactFrame {
  double nx = 0, ny = 0;        // contact normal, unit, from i towards the other body
  double rho_t = 0, rho_n = 0;  // i's centre relative to the other body's fixed point, on t and n (m)
  double arm = 0;               // i's lever arm to the contact point (m); 0: no frame (not touching)
  double theta_i = 0, theta_o = 0;  // angles of i and of the other body (rad)
};

// Relative tangential displacement of the contact points from frame a to frame b (m), along b's t.
inline double tangential_displacement(const ContactFrame& a, const ContactFrame& b) {
  const double cross = a.nx * b.ny - a.ny * b.nx, dot = a.nx * b.nx + a.ny * b.ny;
  const double turned = cross == 0 ? 0.0 : std::atan2(cross, dot);  // phi_b - phi_a
  const double spun_other = b.theta_o - a.theta_o;
  return (b.rho_t - a.rho_t) + 0.5 * (a.rho_n + b.rho_n) * (turned - spun_other) +
         0.5 * (a.arm + b.arm) * (b.theta_i - a.theta_i - spun_other);
}

// Relative rotation of the two bodies from frame a to frame b (rad): the rolling spring's increment.
inline double relative_rotation(const ContactFrame& a, const ContactFrame& b) {
  return (b.theta_i - a.theta_i) - (b.theta_o - a.theta_o);
}

// Lever arms of two discs in contact: one contact point on the line of centres, in the middle of
// the overlap, so both arms end at the same point (r_i - delta/2 and r_j - delta/2 add up to the
// distance of the centres). Equal and opposite forces at one point keep the total angular
// momentum exactly; full radii as arms would change it by F_t delta per unit time.
inline double pair_arm(double radius, double overlap) { return radius - 0.5 * overlap; }

}  // namespace kiln::contact
