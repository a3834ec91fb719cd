#include "integrators/implicit_solver.h"

#include <chrono>
#include <stdexcept>
#include <string>

#include "src/base/error.h"

namespace kiln {

namespace {

ImplicitSolver* self_of(SUNLinearSolver s) { return static_cast<ImplicitSolver*>(s->content); }

// Conjugate gradients stop at this residual relative to the right-hand side: far below the
// truncation errors the studies measure, and reachable in double precision.
constexpr double cg_tolerance = 1e-12;

class Timer {
 public:
  explicit Timer(double& total) : total_(total), start_(std::chrono::steady_clock::now()) {}
  ~Timer() { total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  double& total_;
  std::chrono::steady_clock::time_point start_;
};

const char* name_of(LinearSolverKind k) {
  switch (k) {
    case LinearSolverKind::cholesky: return "cholesky";
    case LinearSolverKind::cg: return "cg";
  }
  return "?";
}

}  // namespace

ImplicitSolver::ImplicitSolver(LinearSolverKind kind, OdeSystem& system, N_Vector state, SUNContext context)
    : kind_(kind), system_(system) {
  DiffusionJacobian probe;
  if (!system_.diffusion_jacobian(0, N_VGetArrayPointer(state), probe))
    throw std::runtime_error("an IMEX integrator needs the implicit part's diffusion Jacobian");
  handle_ = SUNLinSolNewEmpty(context);
  if (!handle_) throw std::runtime_error("SUNDIALS: SUNLinSolNewEmpty failed");
  handle_->content = this;
  handle_->ops->gettype = type;
  handle_->ops->getid = id;
  handle_->ops->setup = setup;
  handle_->ops->solve = solve;
  handle_->ops->numiters = iterations;
  handle_->ops->free = free_solver;
}

ImplicitSolver::~ImplicitSolver() {
  if (handle_) SUNLinSolFreeEmpty(handle_);
}

void ImplicitSolver::attach(void* arkode_memory) {
  arkode_ = arkode_memory;
  if (ARKStepSetLinearSolver(arkode_, handle_, nullptr) < 0)
    throw std::runtime_error("ARKODE: SetLinearSolver failed for the implicit solver");
}

void ImplicitSolver::refresh() {
  ARKStepGetCurrentGamma(arkode_, &gamma_);
  ARKStepGetCurrentTime(arkode_, &t_);
  N_Vector current = nullptr;
  ARKStepGetCurrentState(arkode_, &current);
  y_ = N_VGetArrayPointer(current);
  system_.diffusion_jacobian(t_, y_, jacobian_);
  const bool same_pattern = jacobian_.row == factored_.row && jacobian_.col == factored_.col &&
                            jacobian_.weight.size() == factored_.weight.size();
  if (same_pattern && gamma_ == factored_gamma_ && jacobian_.value == factored_.value &&
      jacobian_.weight == factored_.weight)
    return;
  const int n = static_cast<int>(jacobian_.weight.size());
  triplets_.clear();
  for (int i = 0; i < n; ++i) triplets_.emplace_back(i, i, jacobian_.weight[i]);
  for (size_t k = 0; k < jacobian_.value.size(); ++k)
    triplets_.emplace_back(jacobian_.row[k], jacobian_.col[k], gamma_ * jacobian_.value[k]);
  matrix_.resize(n, n);
  matrix_.setFromTriplets(triplets_.begin(), triplets_.end());
  if (kind_ == LinearSolverKind::cholesky) {
    if (!same_pattern) cholesky_.analyzePattern(matrix_);
    cholesky_.factorize(matrix_);
    if (cholesky_.info() != Eigen::Success)
      // C + gamma dt G is positive definite in exact arithmetic (capacities > 0, conductances >= 0):
      // a failed factorisation is round-off, capacities too small against conductance x step
      // (kiln check refuses dt lambda_max > 1e13 at t = 0; contacts formed later can exceed it).
      throw InstabilityError("instability at t = " + std::to_string(t_) + " s: the implicit stage matrix C + gamma dt G " +
                             "lost its positive definiteness to round-off (heat capacities too small against the "
                             "conductances times the step); lower dt (kiln check gives the thermal relaxation time)");
  } else {
    cg_.setTolerance(cg_tolerance);
    cg_.compute(matrix_);
  }
  std::swap(factored_, jacobian_);
  factored_gamma_ = gamma_;
  ++factorizations_;
}

void ImplicitSolver::solve_block(const double* b, double* x) {
  const DiffusionJacobian& j = factored_;
  const int n = static_cast<int>(j.weight.size());
  rhs_.resize(n);
  for (int i = 0; i < n; ++i) rhs_[i] = j.weight[i] * b[j.first + i];
  if (kind_ == LinearSolverKind::cholesky) {
    block_ = cholesky_.solve(rhs_);
    last_iterations_ = 0;
  } else {
    block_ = cg_.solve(rhs_);
    // Eigen does not count the iteration that converged (from x = 0 at least one always runs).
    last_iterations_ = cg_.iterations() + (cg_.info() == Eigen::Success ? 1 : 0);
    iterations_ += last_iterations_;
  }
  for (int i = 0; i < n; ++i) x[j.first + i] = block_[i];
  if (j.flux >= 0) {
    double flux = 0;
    for (int i = 0; i < n; ++i) flux += j.flux_row[i] * block_[i];
    x[j.flux] = b[j.flux] + gamma_ * flux;
  }
}

int ImplicitSolver::setup(SUNLinearSolver s, SUNMatrix) {
  ImplicitSolver* self = self_of(s);
  Timer timer(self->seconds_);
  self->refresh();
  return 0;
}

int ImplicitSolver::solve(SUNLinearSolver s, SUNMatrix, N_Vector x, N_Vector b, double) {
  ImplicitSolver* self = self_of(s);
  Timer timer(self->seconds_);
  ++self->solves_;
  self->refresh();
  // Components outside the block and the flux: (I - gamma J) is the identity there.
  N_VScale(1.0, b, x);
  self->solve_block(N_VGetArrayPointer(b), N_VGetArrayPointer(x));
  if (self->kind_ == LinearSolverKind::cg && self->cg_.info() != Eigen::Success) return SUNLS_CONV_FAIL;
  return 0;
}


int ImplicitSolver::iterations(SUNLinearSolver s) { return static_cast<int>(self_of(s)->last_iterations_); }

nlohmann::json ImplicitSolver::statistics() const {
  return {{"linear_solver", name_of(kind_)},
          {"linear_solves", solves_},
          {"factorizations", kind_ == LinearSolverKind::cholesky ? factorizations_ : 0},
          {"linear_iterations", iterations_},
          {"linear_solver_seconds", seconds_}};
}

}  // namespace kiln
