#include "src/base/symmetric_eigen.h"

#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/SymEigsSolver.h>

#include <algorithm>
#include <stdexcept>

namespace kiln {

Eigenpairs largest_eigenpairs(const Eigen::SparseMatrix<double>& a, int count) {
  const int n = static_cast<int>(a.rows());
  Eigenpairs out;
  count = std::min(count, n);
  if (count <= 0) return out;
  if (n <= dense_limit) {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> dense{Eigen::MatrixXd(a)};
    out.values = dense.eigenvalues().tail(count).reverse();                // ascending -> largest first
    out.vectors = dense.eigenvectors().rightCols(count).rowwise().reverse();
    return out;
  }
  Spectra::SparseSymMatProd<double> product(a);
  // Spectra wants 2 count < ncv <= n; more Lanczos vectors converge in fewer restarts.
  Spectra::SymEigsSolver<Spectra::SparseSymMatProd<double>> lanczos(product, count, std::min(n, 3 * count + 20));
  lanczos.init();
  lanczos.compute(Spectra::SortRule::LargestAlge, 2000, 1e-10);
  if (lanczos.info() != Spectra::CompInfo::Successful)
    throw std::runtime_error("the Lanczos iteration for the largest eigenvalues did not converge");
  out.values = lanczos.eigenvalues();
  out.vectors = lanczos.eigenvectors();
  return out;
}

}  // namespace kiln
