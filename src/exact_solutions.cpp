#include "src/exact_solutions.h"

#include <Eigen/Dense>
#include <cmath>

#include "contact/normal_force.h"
#include "src/dem_system.h"

namespace kiln {

namespace {

// One disc and a floor at y = 0 with the linear spring-dashpot and gravity (T1, the harmonic
// contact): free flight and contact phases in closed form, one after the other.
// Contact: overlap d = r - y obeys d'' + 2 zeta w d' + w^2 d = g, a damped oscillator about
// g / w^2; flight: y'' = -g.
std::pair<double, double> disc_on_floor(const Scene& s, double t_end) {
  const double r = s.radius[0], g = -s.gravity.y;
  const double m = disc_mass(s, r, s.materials[s.material[0]].density);
  const int wall_material = s.walls.front().material;
  const PairLaw& law = s.law(s.material[0], wall_material);
  const double w = std::sqrt(law.stiffness / m);
  const double zeta = contact::restitution_damping(law.restitution, false, true) / 2;
  const double wd = w * std::sqrt(1 - zeta * zeta);
  double t = 0, y = s.position[0].y, v = s.velocity[0].y;
  while (true) {
    if (y > r || v > 0) {
      // Flight until the disc touches (y = r again), or the end.
      const double land = (v + std::sqrt(v * v + 2 * g * (y - r))) / g;
      if (t + land >= t_end) {
        const double tau = t_end - t;
        return {y + v * tau - 0.5 * g * tau * tau, v - g * tau};
      }
      t += land;
      v -= g * land;
      y = r;
    }
    // Contact from overlap r - y with rate -v, until the overlap returns to zero, or the end.
    const double eq = g / (w * w), a = (r - y) - eq, rate = -v;
    const double b = (rate + zeta * w * a) / wd;
    auto overlap = [&](double tau) {
      return eq + std::exp(-zeta * w * tau) * (a * std::cos(wd * tau) + b * std::sin(wd * tau));
    };
    auto overlap_rate = [&](double tau) {
      return std::exp(-zeta * w * tau) *
             ((-zeta * w * a + wd * b) * std::cos(wd * tau) + (-zeta * w * b - wd * a) * std::sin(wd * tau));
    };
    const double left = t_end - t, step = M_PI / wd / 64;
    double lo = 0, hi = 0;
    bool opens = false;
    while (!opens && hi < left) {
      lo = hi;
      hi = std::min(left, hi + step);
      opens = overlap(hi) < 0;
    }
    if (!opens) return {r - overlap(left), -overlap_rate(left)};
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (overlap(mid) >= 0 ? lo : hi) = mid;
    }
    t += lo;
    y = r;
    v = -overlap_rate(lo);
  }
}

// A thermal scene with frozen mechanics is a linear network with constant conductances:
//   C dT/dt = -K T + b,  K the Laplacian of the contact conductances plus the wall conductances on
// its diagonal, b_i = sum_w H_iw T_w (isothermal walls at constant temperatures only).
// With u = C^(1/2) T, u' = -A u + C^(-1/2) b and A = C^(-1/2) K C^(-1/2) = V diag(l) V^T symmetric,
// each mode w_k = (V^T u)_k decays as w_k(t) = w_k(0) e^(-l_k t) + beta_k (1 - e^(-l_k t)) / l_k
// (beta_k t for l_k = 0): exact up to the eigen-solver's round-off. This covers T4, F1, F2, N1.
std::optional<std::vector<double>> frozen_network_temperatures(const Scene& s, double t) {
  std::vector<double> wall_temperature(s.walls.size(), 0.0);
  for (size_t w = 0; w < s.walls.size(); ++w) {
    const thermal::WallTemperature& wt = s.walls[w].temperature;
    if (!wt.isothermal()) continue;
    for (double v : wt.values)
      if (v != wt.values.front()) return std::nullopt;  // a schedule: no closed form here
    wall_temperature[w] = wt.values.front();
  }
  DemSystem system(s);
  std::vector<double> y = system.initial_state();
  system.prepare(0, y.data(), 0);
  const int n = system.particles();
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n), inv_sqrt_c(n), u(n);
  for (const ConductanceLink& l : system.conduction_links(0, y.data())) {
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
    inv_sqrt_c(i) = 1 / std::sqrt(system.heat_capacity(i));
    u(i) = s.temperature[i] / inv_sqrt_c(i);
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

}  // namespace

std::optional<std::vector<double>> exact_quantity(const Scene& s, const std::string& q, double t) {
  if ((s.name == "t1_free_fall" || s.name == "t1_free_fall_damped" || s.name == "harmonic_contact_pair") &&
      (q == "position" || q == "velocity")) {
    const auto [y, v] = disc_on_floor(s, t);
    return q == "position" ? std::vector<double>{s.position[0].x, y} : std::vector<double>{s.velocity[0].x, v};
  }
  if (s.thermal && s.frozen && q == "temperature") {
    if (auto T = frozen_network_temperatures(s, t)) return T;
  }
  if (s.name == "c1_incline_roll_slide" && q == "incline_acceleration") {
    // Rolling without slip when tan(theta) <= mu (1 + m r^2 / I), else sliding.
    const double along = s.gravity.x, normal = -s.gravity.y;
    const double inertia_ratio = s.mass_model == MassModel::sphere ? 0.4 : 0.5;  // I / (m r^2)
    const double mu = s.law(s.material[0], s.walls.front().material).friction;
    const bool rolls = along / normal <= mu * (1 + 1 / inertia_ratio);
    return std::vector<double>{rolls ? along / (1 + inertia_ratio) : along - mu * normal};
  }
  return std::nullopt;
}

std::string exact_solutions_known() {
  return "position and velocity of t1_free_fall, t1_free_fall_damped, harmonic_contact_pair; temperature of "
         "every thermal scene with frozen mechanics and constant wall temperatures (t4, f1, f2, n1); "
         "incline_acceleration of c1_incline_roll_slide";
}

}  // namespace kiln
