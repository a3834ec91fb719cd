#include "integrators/stability_region.h"

#include <cstdio>  // arkode_butcher.h uses FILE without including it

#include <arkode/arkode_butcher.h>

#include <algorithm>
#include <stdexcept>

#include "integrators/arkode.h"
#include "src/base/error.h"

namespace kiln {

StabilityFunction::StabilityFunction(const std::string& erk_table) {
  ARKodeButcherTable t = load_butcher_table(erk_table, false);
  stages_ = t->stages;
  if (stages_ > 32) throw std::runtime_error("Butcher table " + erk_table + " has more than 32 stages");
  a_.assign(static_cast<size_t>(stages_) * stages_, 0.0);
  for (int i = 0; i < stages_; ++i) {
    b_.push_back(t->b[i]);
    for (int j = 0; j < i; ++j) a_[i * stages_ + j] = t->A[i][j];
  }
  ARKodeButcherTable_Free(t);
}

std::complex<double> StabilityFunction::operator()(std::complex<double> z) const {
  // The stages of y' = lambda y from y = 1: Y_i = 1 + z sum_j a_ij Y_j; then R = 1 + z sum_i b_i Y_i.
  std::complex<double> stage[32], r = 1;
  for (int i = 0; i < stages_; ++i) {
    std::complex<double> sum = 0;
    for (int j = 0; j < i; ++j) sum += a_[i * stages_ + j] * stage[j];
    stage[i] = 1.0 + z * sum;
    r += z * b_[i] * stage[i];
  }
  return r;
}

double reach_along(const StabilityFunction& r, std::complex<double> direction) {
  auto stable = [&](double s) { return std::abs(r(s * direction)) <= 1 + growth_per_step; };
  constexpr double step = 0.01, farthest = 50;
  double lo = 0, hi = 0;
  for (double s = step; s <= farthest; s += step) {
    if (!stable(s)) {
      hi = s;
      break;
    }
    lo = s;
  }
  if (hi == 0) return farthest;
  for (int k = 0; k < 50; ++k) (stable(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
  return lo;
}

namespace {

// q'' = -K q - C q' as a system for the integrators: y = [q | v], no first-order part.
class LinearModes final : public OdeSystem {
 public:
  LinearModes(const Eigen::MatrixXd& k, const Eigen::MatrixXd& c) : k_(k), c_(c) {}
  StateLayout layout() const override { return {static_cast<int>(k_.rows()), 0}; }
  void prepare(double, const double*, double) override {}
  void accept(double) override {}
  void derivative(double, const double* y, double* ydot) override {
    const int n = static_cast<int>(k_.rows());
    const Eigen::Map<const Eigen::VectorXd> q(y, n), v(y + n, n);
    Eigen::Map<Eigen::VectorXd>(ydot, n) = v;
    Eigen::Map<Eigen::VectorXd>(ydot + n, n) = -k_ * q - c_ * v;
  }

 private:
  const Eigen::MatrixXd &k_, &c_;
};

// One step of length h of the scheme as a linear map. A Verlet scheme carries more than y from one
// step to the next (the latest rates, seen with an estimated velocity; BasicVerlet's half-step
// velocities): the map acts on y and on every real array of its checkpoint but its times, all
// read and written through state()/resume(), so nothing here knows a scheme's internals.
Eigen::MatrixXd amplification(const IntegratorInfo& info, LinearModes& modes, double h) {
  const int n = modes.layout().size();
  std::vector<double> y(n, 0.0);
  Snapshot zero;
  {
    const std::unique_ptr<Integrator> scheme = make_integrator(info.name);
    scheme->start(modes, 0, y.data(), h);
    SnapshotFields out(zero, "");
    scheme->state(out);
  }
  std::vector<std::string> carried;
  int size = n;
  for (const std::string& key : zero.real_keys())
    if (key != "time") {
      carried.push_back(key);
      size += static_cast<int>(zero.reals(key).size());
    }
  auto unpack = [&](const Eigen::VectorXd& x, Snapshot& s) {
    std::copy_n(x.data(), n, y.data());
    int at = n;
    for (const std::string& key : carried) {
      std::vector<double> part(zero.reals(key).size());
      std::copy_n(x.data() + at, part.size(), part.data());
      at += static_cast<int>(part.size());
      s.put(key, part);
    }
  };
  auto pack = [&](const Snapshot& s, Eigen::Ref<Eigen::VectorXd> x) {
    std::copy_n(y.data(), n, x.data());
    int at = n;
    for (const std::string& key : carried)
      for (double value : s.reals(key)) x[at++] = value;
  };
  Eigen::MatrixXd g(size, size);
  for (int col = 0; col < size; ++col) {
    Snapshot from = zero;
    unpack(Eigen::VectorXd::Unit(size, col), from);
    const std::unique_ptr<Integrator> scheme = make_integrator(info.name);
    scheme->resume(modes, y.data(), h, from, "");
    scheme->step();
    Snapshot to;
    SnapshotFields out(to, "");
    scheme->state(out);
    pack(to, g.col(col));
  }
  return g;
}

// g balanced by a diagonal similarity (Parlett and Reinsch, "Balancing a matrix for calculation of
// eigenvalues and eigenvectors", Numer. Math. 13, 1969): the map's columns mix positions (m),
// velocities (m/s) and accelerations (m/s^2), entries 1e-12 beside 2e7 for a stiff contact, and
// unbalanced the eigenvalues come out 1e-5 off the unit circle, a stable spring judged unstable.
// Powers of two keep the scaling exact. The eigenvectors are those of D^-1 g D: the binding mode's
// shape is read back through D.
Eigen::MatrixXd balanced(Eigen::MatrixXd g, Eigen::VectorXd& d) {
  const Eigen::Index n = g.rows();
  d = Eigen::VectorXd::Ones(n);
  for (bool changed = true; changed;) {
    changed = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double c = g.col(i).lpNorm<1>() - std::abs(g(i, i)), r = g.row(i).lpNorm<1>() - std::abs(g(i, i));
      if (!(c > 0 && r > 0)) continue;
      int e = 0;
      std::frexp(std::sqrt(r / c), &e);
      const double f = std::ldexp(1.0, e - 1);
      if (f == 1 || (c * f + r / f) >= 0.95 * (c + r)) continue;
      g.col(i) *= f;
      g.row(i) /= f;
      d[i] *= f;
      changed = true;
    }
  }
  return g;
}

// The scale of the fastest mode (1/s): the largest of sqrt(lambda_max(K)) and lambda_max(C).
double fastest_rate(const Eigen::MatrixXd& k, const Eigen::MatrixXd& c) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ek(k, Eigen::EigenvaluesOnly), ec(c, Eigen::EigenvaluesOnly);
  return std::max(std::sqrt(std::max(0.0, ek.eigenvalues().maxCoeff())), std::max(0.0, ec.eigenvalues().maxCoeff()));
}

StepLimit verlet_limit(const IntegratorInfo& info, const Eigen::MatrixXd& k, const Eigen::MatrixXd& c) {
  StepLimit out;
  const double rate = fastest_rate(k, c);
  if (!(rate > 0)) return out;
  // Time in units of 1/rate: K / rate^2 and C / rate, steps dt rate. The step map is the same
  // (its velocities and carried rates scaled by powers of rate, a similarity), but its entries
  // span a few orders instead of hundreds: at rate 1e131 (a disc of 1e-250 kg/m^3) they ran from
  // 1e-132 to 1e262, no balancing evened them, and every step was judged unstable ("no stable
  // step", and the run died of NaN).
  const Eigen::MatrixXd k_scaled = k / rate / rate, c_scaled = c / rate;
  LinearModes modes(k_scaled, c_scaled);
  // A free body's translation is a Jordan block at 1 whose computed eigenvalues split by the
  // square root of the round-off (1e-8), below growth_per_step.
  auto radius = [&](double h, Eigen::VectorXcd* shape) {
    Eigen::VectorXd d;
    const Eigen::EigenSolver<Eigen::MatrixXd> eig(balanced(amplification(info, modes, h), d), shape != nullptr);
    Eigen::Index at = 0;
    const double rho = eig.eigenvalues().cwiseAbs().maxCoeff(&at);
    if (shape) {
      *shape = (d.cast<std::complex<double>>().asDiagonal() * eig.eigenvectors().col(at)).head(k.rows());
      out.eigenvalue = eig.eigenvalues()[at];
    }
    return rho;
  };
  auto stable = [&](double h) { return radius(h, nullptr) <= 1 + growth_per_step; };
  // The scan starts at dt rate = 0.1 (60 steps a period): a limit below it is still found, by the
  // bisection from 0. Each probe is an eigenvalue solve of the step map, the cost of the estimate.
  double lo = 0, hi = 0;
  for (double s = 0.1; s < 100; s *= 1.05) {
    if (!stable(s)) {
      hi = s;
      break;
    }
    lo = s;
  }
  if (hi == 0) return out;  // stable however long the step (no spring nor dashpot binds)
  for (int it = 0; it < 50 && hi - lo > 1e-9 * hi; ++it) (stable(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
  out.dt = lo / rate;
  radius(hi * (1 + 1e-6), &out.shape);
  return out;
}

StepLimit erk_limit(const IntegratorInfo& info, const Eigen::MatrixXd& k, const Eigen::MatrixXd& c) {
  StepLimit out;
  const StabilityFunction r(info.erk_table);
  const Eigen::Index n = k.rows();
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  j.topRightCorner(n, n).setIdentity();
  j.bottomLeftCorner(n, n) = -k;
  j.bottomRightCorner(n, n) = -c;
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(j);
  const double scale = eig.eigenvalues().cwiseAbs().maxCoeff();
  for (Eigen::Index m = 0; m < eig.eigenvalues().size(); ++m) {
    const std::complex<double> lambda = eig.eigenvalues()[m];
    if (std::abs(lambda) <= 1e-9 * scale) continue;  // a free body's neutral motion
    const double dt = reach_along(r, lambda / std::abs(lambda)) / std::abs(lambda);
    if (dt < out.dt) {
      out.dt = dt;
      out.eigenvalue = lambda;
      out.shape = eig.eigenvectors().col(m).head(n);
    }
  }
  return out;
}

}  // namespace

StepLimit mechanical_step_limit(const IntegratorInfo& info, const Eigen::MatrixXd& k, const Eigen::MatrixXd& c) {
  if (!info.integrates_contacts)
    throw InputError("integrator '" + info.name + "' integrates heat on frozen networks only: no mechanical step");
  if (k.rows() == 0) return {};
  // A spring or dashpot over a mass beyond double precision (tangential_stiffness_ratio 1e300: the
  // mode was then "unresolved", warned about and run): no step is a number, for the caller to refuse.
  if (!k.allFinite() || !c.allFinite()) {
    StepLimit nan;
    nan.dt = NAN;
    return nan;
  }
  return info.scheme == IntegratorScheme::arkode ? erk_limit(info, k, c) : verlet_limit(info, k, c);
}

StabilityIntervals stability_intervals(const IntegratorInfo& info) {
  StabilityIntervals out;
  if (info.scheme == IntegratorScheme::arkode) {
    const StabilityFunction r(info.erk_table);
    out.imaginary = reach_along(r, {0, 1});
    out.negative_real = reach_along(r, {-1, 0});
    return out;
  }
  // A unit spring and a unit dashpot, each alone.
  const Eigen::MatrixXd one = Eigen::MatrixXd::Ones(1, 1), none = Eigen::MatrixXd::Zero(1, 1);
  out.imaginary = verlet_limit(info, one, none).dt;
  out.negative_real = verlet_limit(info, none, one).dt;
  return out;
}

}  // namespace kiln
