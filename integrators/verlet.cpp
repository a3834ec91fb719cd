#include "integrators/verlet.h"

#include <algorithm>

namespace kiln {

void BasicVerlet::start_without_evaluating(OdeSystem& system, double* y, double dt) {
  VerletFamily::start_without_evaluating(system, y, dt);
  ahead_.assign(layout_.nq, 0);
  eval_.assign(layout_.size(), 0);
  zrate_.assign(layout_.nz, 0);
  z_before_.assign(layout_.nz, 0);
}

void BasicVerlet::start(OdeSystem& system, double t0, double* y, double dt) {
  bind(system, t0, y, dt);
  const int nq = layout_.nq, nz = layout_.nz;
  const double* a = accel();
  for (int k = 0; k < nq; ++k) ahead_[k] = y[k] + dt * y[nq + k] + 0.5 * dt * dt * a[k];  // II.20
  std::copy_n(zrate(), nz, zrate_.data());
}

void BasicVerlet::step() {
  const int nq = layout_.nq, nz = layout_.nz;
  const double h = step_length();
  double *q = this->q(), *v = this->v(), *z = this->z();
  if (h != dt_) {  // a shorter last step: x_{n+1} again from x_n, v_n and a_n (II.20)
    const double* a = accel();
    for (int k = 0; k < nq; ++k) ahead_[k] = q[k] + h * v[k] + 0.5 * h * h * a[k];
  }
  // The force at x_{n+1}: positions known, velocity by backward difference, z by forward Euler.
  for (int k = 0; k < nq; ++k) {
    eval_[k] = ahead_[k];
    eval_[nq + k] = (ahead_[k] - q[k]) / h;
  }
  // works: trapezoidal forces times the displacement x_{n+1} - x_n = h eval_v
  if (works_ > 0) work_before(eval_.data() + nq, h);
  std::copy_n(z, nz, z_before_.data());
  for (int k = 0; k < nz; ++k) z[k] += h * zrate_[k];
  std::copy_n(z, nz, eval_.data() + 2 * nq);
  const double t_next = next_time();
  evaluate(t_next, eval_.data(), 0);
  if (works_ > 0) {
    work_after(eval_.data() + nq, eval_.data() + nq, h);
    book_work(z_before_.data(), eval_.data() + nq, h, h, 0.0);
  }
  const double* a = accel();
  for (int k = 0; k < nq; ++k) {
    const double x_prev = q[k];
    const double x_after = 2 * ahead_[k] - x_prev + h * h * a[k];  // II.16
    v[k] = (x_after - x_prev) / (2 * h);                            // II.21
    q[k] = ahead_[k];
    ahead_[k] = x_after;
  }
  std::copy_n(zrate(), nz, zrate_.data());
  advance_time();
  ++stats_.steps;
}

}  // namespace kiln
