// How a run's steps are controlled: tolerances of adaptive stepping, contact events, the implicit
// stages' linear solver. Part of a scene; read by the integrators.
#pragma once
#include <cmath>

namespace kiln {

// Step-size control. rtol > 0 makes adaptive integrators adapt (starting from dt); fixed-step
// implicit solves still use rtol/atol to stop their iterations, so they get tight defaults.
// How the implicit stages' linear systems (I - gamma J) x = b are solved (IMEX pairs), both on the
// symmetric form W + gamma S of a diffusion Jacobian (DiffusionJacobian):
//  - cholesky: exact, a sparse Cholesky (LDL^T), refactored only when gamma or the network changes;
//  - cg: conjugate gradients with a diagonal preconditioner.
// SUNDIALS' matrix-free SPGMR was measured and dropped (integrators/implicit_solver.h).
enum class LinearSolverKind { cholesky, cg };

struct StepControl {
  double rtol = 0;
  double atol = 0;  // scalar absolute tolerance, for every field not given below
  double atol_position = NAN, atol_velocity = NAN, atol_angle = NAN, atol_temperature = NAN;
  // Discontinuity locking: which contacts act is frozen within a step; each onset and release
  // is located by root finding and the method restarts there (ARKODE integrators).
  bool contact_events = false;
  LinearSolverKind linear_solver = LinearSolverKind::cholesky;
};

}  // namespace kiln
