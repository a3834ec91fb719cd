#include "src/base/symmetric_eigen.h"

#include <Spectra/SymEigsSolver.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace kiln {

namespace {

// Spectra's interface to an operator: its products, by pointer.
// Spectra's interface to an operator: its products, by pointer, times 2^-exponent (a product by a
// power of two: exact, and a multiplication where ldexp was a library call per entry).
struct SpectraProduct {
  using Scalar = double;
  const SymmetricOperator& a;
  int exponent = 0;
  Eigen::Index rows() const { return a.rows(); }
  Eigen::Index cols() const { return a.rows(); }
  void perform_op(const double* x, double* y) const {
    a.apply(x, y);
    if (exponent == 0) return;
    // In two halves: 2^-exponent alone is infinite or subnormal for an operator of subnormal size.
    const double first = std::ldexp(1.0, -exponent / 2), second = std::ldexp(1.0, exponent / 2 - exponent);
    for (Eigen::Index i = 0; i < rows(); ++i) y[i] = y[i] * first * second;
  }
};

struct SparseProduct final : SymmetricOperator {
  const Eigen::SparseMatrix<double>& a;
  explicit SparseProduct(const Eigen::SparseMatrix<double>& m) : a(m) {}
  int rows() const override { return static_cast<int>(a.rows()); }
  void apply(const double* x, double* y) const override {
    Eigen::Map<Eigen::VectorXd>(y, a.rows()).noalias() = a * Eigen::Map<const Eigen::VectorXd>(x, a.cols());
  }
};

}  // namespace

Eigenpairs largest_eigenpairs(const SymmetricOperator& a, int count) {
  const int n = a.rows();
  Eigenpairs out;
  count = std::min(count, n);
  if (count <= 0) return out;
  if (n <= dense_limit) {
    Eigen::MatrixXd dense(n, n);
    Eigen::VectorXd unit = Eigen::VectorXd::Zero(n);
    for (int c = 0; c < n; ++c) {
      unit[c] = 1;
      a.apply(unit.data(), dense.col(c).data());
      unit[c] = 0;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(dense);
    out.values = solver.eigenvalues().tail(count).reverse();  // ascending -> largest first
    out.vectors = solver.eigenvectors().rightCols(count).rowwise().reverse();
    return out;
  }
  // Spectra wants count < ncv <= n. Its n x ncv Lanczos basis is the estimate's largest array
  // (ncv doubles per coordinate, more than a step's whole state); 2 count + 8 vectors converge in
  // a few restarts more than 3 count + 20 did, with 40 % less memory.
  // The operator scaled by a power of two near its size, seen in one product with an unbiased
  // vector, so that Lanczos' norms neither overflow nor underflow (as for a matrix, below).
  Eigen::VectorXd probe = Eigen::VectorXd::LinSpaced(n, -1.0, 1.0).array().sin() + 0.5, image(n);
  a.apply(probe.data(), image.data());
  const double size = image.cwiseAbs().maxCoeff();
  if (!std::isfinite(size)) {
    out.values = Eigen::VectorXd::Constant(count, NAN);
    out.vectors = Eigen::MatrixXd::Zero(n, count);
    return out;
  }
  SpectraProduct product{a, size > 0 ? std::ilogb(size) : 0};
  Spectra::SymEigsSolver<SpectraProduct> lanczos(product, count, std::min(n, 2 * count + 8));
  lanczos.init();
  // Converged when each Ritz pair's residual is below 1e-7 |value|, which bounds the value's error
  // (|lambda - theta| <= |r| for a symmetric operator; in practice |r|^2 / gap): a step limit to
  // 5e-8. On the 10,000 pile the limit agrees with 1e-10's to 12 digits; the 100,000 pile's
  // estimate took 60 s instead of 93.
  lanczos.compute(Spectra::SortRule::LargestAlge, 2000, 1e-7);
  if (lanczos.info() != Spectra::CompInfo::Successful)
    throw std::runtime_error("the Lanczos iteration for the largest eigenvalues did not converge");
  out.values = lanczos.eigenvalues();
  for (double& v : out.values) v = std::ldexp(v, product.exponent);
  out.vectors = lanczos.eigenvectors();
  return out;
}

// Solved for the matrix scaled by a power of two that brings its largest entry near 1 (exact: the
// values are scaled back without rounding), so that entries near the ends of double precision do
// not overflow or underflow inside the solver: a conductance network of specific heat 1e-300 has
// entries near 1e300, whose squares in the tridiagonalisation were infinite and its largest
// eigenvalue NaN, read as "no conducting contact" (issue 28). An entry that is not finite makes
// every value NaN, for the caller to refuse.
Eigenpairs largest_eigenpairs(const Eigen::SparseMatrix<double>& a, int count) {
  // Over the stored entries (coeffs() of a matrix not compressed holds unused slots too).
  double largest = 0;
  for (Eigen::Index k = 0; k < a.outerSize(); ++k)
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, k); it; ++it)
      largest = std::isnan(it.value()) ? it.value() : std::max(largest, std::abs(it.value()));
  if (!std::isfinite(largest)) {
    Eigenpairs out;
    out.values = Eigen::VectorXd::Constant(std::min<Eigen::Index>(count, a.rows()), NAN);
    out.vectors = Eigen::MatrixXd::Zero(a.rows(), out.values.size());
    return out;
  }
  const int exponent = largest > 0 ? std::ilogb(largest) : 0;
  // In two halves, as SpectraProduct does.
  Eigen::SparseMatrix<double> scaled = a * std::ldexp(1.0, -exponent / 2);
  scaled *= std::ldexp(1.0, exponent / 2 - exponent);
  Eigenpairs out = largest_eigenpairs(SparseProduct(scaled), count);
  for (double& v : out.values) v = std::ldexp(v, exponent);
  return out;
}

}  // namespace kiln
