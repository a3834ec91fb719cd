#include "src/studies/network_exact.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace kiln::thermal {

std::vector<double> exact_network_temperatures(const std::vector<ConductanceLink>& links,
                                               const std::vector<double>& capacity,
                                               const std::vector<double>& wall_temperature,
                                               const std::vector<double>& initial, double t) {
  const int n = static_cast<int>(capacity.size());
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n), inv_sqrt_c(n), u(n);
  for (const ConductanceLink& l : links) {
    K(l.i, l.i) += l.h;
    if (l.j >= 0) {
      K(l.j, l.j) += l.h;
      K(l.i, l.j) -= l.h;
      K(l.j, l.i) -= l.h;
    } else {
      b(l.i) += l.h * wall_temperature[-1 - l.j];
    }
  }
  for (int i = 0; i < n; ++i) {
    inv_sqrt_c(i) = 1 / std::sqrt(capacity[i]);
    u(i) = initial[i] / inv_sqrt_c(i);
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(inv_sqrt_c.asDiagonal() * K * inv_sqrt_c.asDiagonal());
  const Eigen::VectorXd w0 = eig.eigenvectors().transpose() * u;
  const Eigen::VectorXd beta = eig.eigenvectors().transpose() * inv_sqrt_c.cwiseProduct(b);
  const double scale = std::max(eig.eigenvalues().cwiseAbs().maxCoeff(), 1e-300);
  Eigen::VectorXd w(n);
  for (int k = 0; k < n; ++k) {
    const double l = eig.eigenvalues()(k);
    w(k) = std::abs(l) < 1e-12 * scale ? w0(k) + beta(k) * t
                                       : w0(k) * std::exp(-l * t) - beta(k) * std::expm1(-l * t) / l;
  }
  const Eigen::VectorXd T = inv_sqrt_c.cwiseProduct(eig.eigenvectors() * w);
  return std::vector<double>(T.data(), T.data() + n);
}

}  // namespace kiln::thermal
