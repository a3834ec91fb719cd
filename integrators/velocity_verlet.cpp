#include "integrators/velocity_verlet.h"

#include <algorithm>

namespace kiln {

void VelocityVerlet::start(OdeSystem& system, double t0, double* y, double dt) {
  system_ = &system;
  layout_ = system.layout();
  y_ = y;
  t_ = t0;
  dt_ = dt;
  rate_.assign(layout_.size(), 0);
  v_half_.assign(layout_.nq, 0);
  z_old_.assign(layout_.nz, 0);
  zrate_old_.assign(layout_.nz, 0);
  system.prepare(t0, y, dt);
  system.derivative(t0, y, rate_.data());
  system.accept(t0);
  ++stats_.rhs_evals;
}

void VelocityVerlet::step() {
  const int nq = layout_.nq, nz = layout_.nz;
  const double h = dt_;
  double* q = y_;
  double* v = y_ + nq;
  double* z = y_ + 2 * nq;
  const double* a = rate_.data() + nq;
  const double* zrate = rate_.data() + 2 * nq;
  for (int k = 0; k < nq; ++k) {
    v_half_[k] = v[k] + 0.5 * h * a[k];  // II.25
    q[k] += h * v_half_[k];              // II.26
    v[k] = predicted_ ? v_half_[k] + 0.5 * h * a[k] : v_half_[k];  // v* seen by the force
  }
  std::copy_n(z, nz, z_old_.data());
  std::copy_n(zrate, nz, zrate_old_.data());
  for (int k = 0; k < nz; ++k) z[k] += h * zrate_old_[k];

  const double t_next = t_ + h;
  system_->prepare(t_next, y_, 0);
  system_->derivative(t_next, y_, rate_.data());
  system_->accept(t_next);
  ++stats_.rhs_evals;

  for (int k = 0; k < nq; ++k) v[k] = v_half_[k] + 0.5 * h * a[k];  // II.27 with a = a_{n+1}
  for (int k = 0; k < nz; ++k) z[k] = z_old_[k] + 0.5 * h * (zrate_old_[k] + zrate[k]);
  t_ = t_next;
  ++stats_.steps;
}

}  // namespace kiln
