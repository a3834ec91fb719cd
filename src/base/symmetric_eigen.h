// The largest eigenpairs of a symmetric operator: what a stability limit needs of a scene's
// mass-scaled stiffness, damping and conductance operators (src/run/linearised_dynamics.h).
// Below dense_limit rows the operator is assembled and decomposed whole (Eigen's
// SelfAdjointEigenSolver, tridiagonalisation and QR: every eigenpair, exact to round-off); above
// it the implicitly restarted Lanczos method of Spectra (Yixuan Qiu, "Spectra: Sparse Eigenvalue
// Computation Toolkit as a Redesigned ARPACK", 2015-2023; the method: Lehoucq and Sorensen,
// "Deflation techniques for an implicitly restarted Arnoldi iteration", SIAM J. Matrix Anal. Appl.
// 17, 1996) finds the largest few from products alone, so the operator need never be stored.
#pragma once
#include <Eigen/Dense>
#include <Eigen/Sparse>

namespace kiln {

struct Eigenpairs {
  Eigen::VectorXd values;   // largest first
  Eigen::MatrixXd vectors;  // column k belongs to values[k]; orthonormal
};

// A symmetric linear operator known by its products y = A x (x and y of rows() entries).
class SymmetricOperator {
 public:
  virtual ~SymmetricOperator() = default;
  virtual int rows() const = 0;
  virtual void apply(const double* x, double* y) const = 0;
};

// The `count` algebraically largest eigenpairs of `a` (fewer when a has fewer rows).
// Throws std::runtime_error when the Lanczos iteration does not converge.
Eigenpairs largest_eigenpairs(const SymmetricOperator& a, int count);
Eigenpairs largest_eigenpairs(const Eigen::SparseMatrix<double>& a, int count);

// Rows up to which largest_eigenpairs decomposes the matrix densely: 0.02 s at 300 rows, while at
// 1200 (all eigenvectors, O(n^3)) it took 2.5 s, where Lanczos takes tenths.
inline constexpr int dense_limit = 300;

}  // namespace kiln
