// The linear solver of ARKODE's implicit stages: (I - gamma J) x = b, J the Jacobian of the
// system's implicit part (heat conduction), as a SUNDIALS matrix-embedded linear solver (ARKODE
// hands it no matrix; it reads gamma and the stage's state from ARKODE and assembles what it needs).
//
// Why not SUNDIALS' matrix-free SPGMR, which kiln used before: with the tight tolerances a fixed-step
// run needs (the solver error must stay below the truncation error), GMRES on a small network
// exhausts its Krylov space before meeting the tolerance and stops on a singular Hessenberg matrix
// (SUNLS_QRFACT_FAIL, 807): T4 under imex4 failed at dt = 0.08 s and ran at 0.075 and 0.085 s.
// Elsewhere it stops at ARKODE's linear tolerance (5 Krylov vectors by default), and with one
// Newton iteration per stage that error stays: on F1 at 30x the explicit limit it put temperatures
// 154 K outside their range. Measured on F1 (imex4, dt 0.43 s): SPGMR 1.6 ms in the solver and a
// wrong result, conjugate gradients 0.46 ms, this Cholesky 0.18 ms; on P1, a moving powder, 0.39 s
// against 0.11 s.
// Conduction is linear, and its Jacobian -C^-1 L is symmetric in the C-weighted form, so the stage
// system (C + gamma L) x = C b is symmetric positive definite: a sparse Cholesky solves it exactly
// once factorized, and the factor is kept while gamma and the network stay (a fixed step on a
// frozen network factorizes once per distinct gamma for the whole run).
#pragma once
#include <arkode/arkode_arkstep.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_linearsolver.h>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <nlohmann/json.hpp>

#include "integrators/integrator.h"

namespace kiln {

class ImplicitSolver {
 public:
  // The system must give a diffusion Jacobian (OdeSystem::diffusion_jacobian).
  ImplicitSolver(LinearSolverKind kind, OdeSystem& system, N_Vector state, SUNContext context);
  ~ImplicitSolver();
  ImplicitSolver(const ImplicitSolver&) = delete;
  ImplicitSolver& operator=(const ImplicitSolver&) = delete;
  // Attaches to ARKStep memory (after ARKStepCreate): sets this as its linear solver.
  void attach(void* arkode_memory);
  // kind, solves, factorizations (cholesky), iterations (cg), seconds inside setup and solve.
  nlohmann::json statistics() const;

 private:
  static SUNLinearSolver_Type type(SUNLinearSolver) { return SUNLINEARSOLVER_MATRIX_EMBEDDED; }
  static SUNLinearSolver_ID id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
  static int setup(SUNLinearSolver s, SUNMatrix);
  static int solve(SUNLinearSolver s, SUNMatrix, N_Vector x, N_Vector b, double tol);  // tol unused: exact or 1e-12
  static int iterations(SUNLinearSolver s);
  static int free_solver(SUNLinearSolver) { return 0; }  // owned by ImplicitSolver

  // Reads gamma, t and the stage state from ARKODE; refactors when gamma or the network changed.
  void refresh();
  void solve_block(const double* b, double* x);

  LinearSolverKind kind_;
  OdeSystem& system_;
  void* arkode_ = nullptr;
  SUNLinearSolver handle_ = nullptr;
  double gamma_ = 0, t_ = 0;
  const double* y_ = nullptr;
  DiffusionJacobian jacobian_, factored_;  // the latest, and the one factorized
  double factored_gamma_ = NAN;
  Eigen::SparseMatrix<double> matrix_;  // W + gamma S, lower triangle
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> cholesky_;
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::DiagonalPreconditioner<double>> cg_;
  Eigen::VectorXd rhs_, block_;
  std::vector<Eigen::Triplet<double>> triplets_;
  long solves_ = 0, factorizations_ = 0, iterations_ = 0, last_iterations_ = 0;
  double seconds_ = 0;
};

}  // namespace kiln
