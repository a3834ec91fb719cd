// A scene's mechanics linearised about a state: M q'' + C q' + K q = 0 over its free
// coordinates, mass-scaled and reduced to the modes that can bind a step
// (integrators/stability_region.h gives each integrator's limit on them).
//
// Coordinates: each free particle's x and y and, when the scene rotates, its angle; each
// load-controlled wall body's position along its load. A particle attached to a wall body moves
// with the body; walls and other attached particles are driven: no coordinate. Each touching
// contact (DemSystem::contact_springs) adds its springs as k B B^T and its dashpots as c B B^T,
// B the contact's relative displacement:
//   normal       n . (u_i - u_j)
//   tangential   t . (u_i - u_j) + arm_i theta_i + arm_j theta_j,  t = perp(n): the contact points' slip
//   rolling      theta_i - theta_j
// (a wall body's part: its displacement along the load, s e, in place of u_j); a wall body's own
// dashpot adds to its diagonal. Mass-scaled, K~ = M^-1/2 K M^-1/2 (1/s^2) and C~ likewise (1/s).
// Left out: the geometric stiffness of the normal force turning with its contact (F_n / distance,
// a fraction overlap / radius of k_n) and gravity, which has none.
//
// The reduction: the 24 stiffest eigenvectors of K~ and the 8 most damped of C~
// (src/base/symmetric_eigen.h), orthonormalised, and K~ and C~ projected on them (Rayleigh-Ritz).
// A scene with fewer coordinates keeps all of them: its modes are exact, the dashpots' coupling
// of the modes included. K~ and C~ are applied from the springs' rows, never assembled: a sparse
// copy took more memory than the run itself (17 MB for 10,000 discs, with 36 MB of triplets).
#pragma once
#include <Eigen/Dense>
#include <array>
#include <string>
#include <vector>

#include "src/dem/dem_system.h"

namespace kiln {

// A spring's relative displacement B in mass-scaled coordinates (B M^-1/2): up to seven
// (coordinate, coefficient) terms, the coefficients in 1/sqrt(kg) (or 1/sqrt(kg m^2) on an angle).
struct SpringRow {
  int at[7];
  double by[7];
  int size = 0;
  void add(int coordinate, double coefficient) {
    if (coordinate < 0 || coefficient == 0) return;
    at[size] = coordinate;
    by[size] = coefficient;
    ++size;
  }
};

struct LinearisedMechanics {
  Eigen::MatrixXd k, c;      // reduced (r x r)
  Eigen::MatrixXd basis;     // n x r, orthonormal columns in the mass-scaled coordinates
  double omega_max = 0;      // the stiffest mode's frequency, sqrt of K~'s largest eigenvalue (rad/s)
  int coordinates = 0;       // n
  // For naming a mode: the contacts and their rows (normal, tangential, rolling), and per wall
  // body its coordinate.
  std::vector<ContactSprings> contacts;
  std::vector<std::array<SpringRow, 3>> rows;
  std::vector<int> body_at;
};

// Which springs enter: all, or only those no cap bounds (normal springs and dashpots, wall
// bodies): a tangential or rolling mode made unstable by the step grows only until its spring
// reaches the Coulomb or rolling cap, while these grow without bound.
enum class Springs { all, uncapped };
LinearisedMechanics linearise_mechanics(const DemSystem& system, double t, const double* y,
                                        Springs springs = Springs::all);

// What a mode is and where it lives: its kind, the one that holds most of its spring energy
// ("normal", "tangential-rotational", "rolling"), or "wall body" when wall bodies carry most of
// its kinetic energy; and the contact that holds most of that energy ("particles 3 and 7",
// "particle 0 on wall floor") or the wall ("wall lid").
// A mode whose shape is lost (a stiffness near double's range, 1e300 N/m, overflows the step
// map's eigenvectors) is still named, as what it is, rather than printed as "its  mode".
struct ModeDescription {
  std::string kind = "unresolved", where = "no contact singled out: its shape was lost to overflow or round-off";
};
ModeDescription describe_mode(const LinearisedMechanics& m, const Eigen::VectorXcd& reduced_shape, const Scene& scene);

}  // namespace kiln
