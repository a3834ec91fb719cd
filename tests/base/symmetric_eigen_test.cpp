// The largest eigenpairs of an operator known only by its products (src/base/symmetric_eigen.h),
// on the path graph's Laplacian, whose spectrum is known: 2 - 2 cos(k pi / (n + 1)), k = 1..n.
#include <catch2/catch.hpp>

#include <cmath>

#include "src/base/symmetric_eigen.h"

using namespace kiln;

namespace {

// tridiag(-1, 2, -1) times `scale`, applied without being stored.
struct PathLaplacian final : SymmetricOperator {
  int n;
  double scale = 1;
  explicit PathLaplacian(int size, double s = 1) : n(size), scale(s) {}
  int rows() const override { return n; }
  void apply(const double* x, double* y) const override {
    for (int i = 0; i < n; ++i) y[i] = scale * (2 * x[i] - (i > 0 ? x[i - 1] : 0.0) - (i + 1 < n ? x[i + 1] : 0.0));
  }
};

double path_eigenvalue(int n, int k) { return 2 - 2 * std::cos(k * M_PI / (n + 1)); }

}  // namespace

TEST_CASE("the path Laplacian's largest eigenpairs come out exact, decomposed whole and by Lanczos", "[eigen]") {
  for (const int n : {dense_limit, 3 * dense_limit}) {
    INFO("rows " << n);
    const PathLaplacian a(n);
    const Eigenpairs e = largest_eigenpairs(a, 6);
    REQUIRE(e.values.size() == 6);
    Eigen::VectorXd product(n);
    for (int c = 0; c < 6; ++c) {
      CHECK(e.values[c] == Approx(path_eigenvalue(n, n - c)).epsilon(1e-9));
      a.apply(e.vectors.col(c).data(), product.data());
      CHECK((product - e.values[c] * e.vectors.col(c)).norm() < 1e-7);
    }
    CHECK((e.vectors.transpose() * e.vectors - Eigen::MatrixXd::Identity(6, 6)).norm() < 1e-9);
  }
}

TEST_CASE("a stored sparse matrix gives the eigenpairs of the same operator applied by products", "[eigen]") {
  const int n = 2 * dense_limit;
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < n; ++i) {
    entries.emplace_back(i, i, 2.0);
    if (i > 0) entries.emplace_back(i, i - 1, -1.0);
    if (i + 1 < n) entries.emplace_back(i, i + 1, -1.0);
  }
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(entries.begin(), entries.end());
  const Eigenpairs stored = largest_eigenpairs(a, 3), applied = largest_eigenpairs(PathLaplacian(n), 3);
  for (int c = 0; c < 3; ++c) CHECK(stored.values[c] == Approx(applied.values[c]).epsilon(1e-12));
}

// Issue 28: a conductance network of specific heat 1e-300 J/(kg K) has entries near 1e300, whose
// squares overflowed inside the solvers (its rate came out NaN, read as "no conducting contact").
// The spectrum scales with the operator, to the ends of double precision.
TEST_CASE("the largest eigenvalues of an operator or matrix scaled by 1e300 or 1e-300 scale with it", "[eigen]") {
  for (const double scale : {1e300, 1e-300}) {
    for (const int n : {dense_limit / 10, 3 * dense_limit}) {
      INFO("scale " << scale << ", rows " << n);
      const Eigenpairs e = largest_eigenpairs(PathLaplacian(n, scale), 2);
      REQUIRE(e.values.size() == 2);
      CHECK(e.values[0] / scale == Approx(path_eigenvalue(n, n)).epsilon(1e-9));
      Eigen::SparseMatrix<double> m(n, n);
      for (int i = 0; i < n; ++i) {
        m.insert(i, i) = 2 * scale;
        if (i > 0) m.insert(i, i - 1) = -scale;
        if (i + 1 < n) m.insert(i, i + 1) = -scale;
      }
      CHECK(largest_eigenpairs(m, 2).values[0] / scale == Approx(path_eigenvalue(n, n)).epsilon(1e-9));
    }
  }
  const Eigenpairs overflowed = largest_eigenpairs(PathLaplacian(3 * dense_limit, INFINITY), 1);
  CHECK(std::isnan(overflowed.values[0]));  // for the caller to refuse, never a number
}
