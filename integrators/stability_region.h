// Where an integrator is stable on a linearised mechanical system, from the integrator's own
// definition.
//
// The modes: q'' = -K q - C q' with K and C symmetric positive semidefinite, the mass-scaled
// stiffness and damping of a scene reduced to a few coordinates (src/run/linearised_dynamics.h);
// K in 1/s^2, C in 1/s. One step of length h maps (q, v) linearly to the next; the step is stable
// when that map's spectral radius is at most 1 + growth_per_step.
//  - An explicit Runge-Kutta table (an IMEX pair's explicit table takes the mechanics): the map is
//    R(hJ), J = [0 I; -K -C], with the table's stability function
//    R(z) = 1 + z b^T (I - z A)^-1 1 (Hairer and Wanner, "Solving Ordinary Differential Equations
//    II", 1996, section IV.2, eq. 2.3): stable when |R(h lambda)| <= 1 for every eigenvalue lambda
//    of J. A dashpot moves its mode's eigenvalues off the imaginary axis, by -c/2.
//  - A Verlet scheme: its map depends on K and C apart (the dashpot sees the half-step velocity,
//    a backward difference or a prediction), so it is measured: the scheme itself steps the
//    reduced system once from each unit state (of y and of what its checkpoint carries between
//    steps, such as the latest acceleration), and the columns are the amplification matrix.
#pragma once
#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <vector>

#include "integrators/integrator.h"

namespace kiln {

// The growth a step may give a mode and still count as stable: e-fold in a million steps. Heun's
// R(iy) = 1 - y^2/2 + iy leaves the unit circle at once (|R|^2 = 1 + y^4/4), so with no allowance an
// undamped spring had a limit of 0.0017 / omega (T1 refused under erk2 at 1e-5 s, though a 1 s run
// gains 3.5e-4 of its energy); with it, 0.053 / omega. It also stands above the 1e-8 by which
// round-off splits a free body's neutral modes off 1.
inline constexpr double growth_per_step = 1e-6;

// R(z) of an explicit Butcher table (A strictly lower triangular), stage by stage.
class StabilityFunction {
 public:
  explicit StabilityFunction(const std::string& erk_table);  // a SUNDIALS table name
  std::complex<double> operator()(std::complex<double> z) const;

 private:
  int stages_ = 0;
  std::vector<double> a_, b_;  // A row-major (stages x stages), b
};

// The first step length at which a mode leaves the region along its ray, in units of 1/|lambda|
// (|lambda| = 1 rad/s: the reach along that direction of the complex plane). Found by a scan in
// steps of 0.01 to 50, then bisection; 0 when even the smallest step is unstable, 50 (or more)
// when the ray stays inside.
double reach_along(const StabilityFunction& r, std::complex<double> direction);

struct StepLimit {
  double dt = INFINITY;        // the largest stable step (s); 0: none is; inf: no mode limits it
  Eigen::VectorXcd shape;      // the binding mode: its position part, in the reduced coordinates
  std::complex<double> eigenvalue = NAN;  // ERK: its eigenvalue of J (1/s); Verlet: of the step map
};

// The step limit of integrator `info` on q'' = -K q - C q' (k x k each). An IMEX pair is judged by
// its explicit table. Throws InputError for imex1, which integrates no contacts.
StepLimit mechanical_step_limit(const IntegratorInfo& info, const Eigen::MatrixXd& k, const Eigen::MatrixXd& c);

// A method's stability interval on the imaginary axis (an undamped spring: stable while
// dt omega is below it; 0 when no step is) and on the negative real axis (a pure dashpot, or a
// conduction mode: stable while dt lambda is below it), in units of dt |lambda|.
struct StabilityIntervals {
  double imaginary = 0, negative_real = 0;
};
StabilityIntervals stability_intervals(const IntegratorInfo& info);

}  // namespace kiln
