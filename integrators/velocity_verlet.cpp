#include "integrators/velocity_verlet.h"

#include <algorithm>

#include "src/base/parallel.h"

namespace kiln {

void VelocityVerlet::start(OdeSystem& system, double t0, double* y, double dt) { bind(system, t0, y, dt); }

void VelocityVerlet::start_without_evaluating(OdeSystem& system, double* y, double dt) {
  VerletFamily::start_without_evaluating(system, y, dt);
  v_half_.assign(layout_.nq, 0);
  z_old_.assign(layout_.nz, 0);
  zrate_old_.assign(layout_.nz, 0);
  slope_correction_ = system.has_implicit_part();
  dz_.assign(slope_correction_ ? layout_.size() : 0, 0.0);
  jdz_ = dz_;
  z_unbooked_.assign(slope_correction_ ? layout_.nz : 0, 0.0);
}

void VelocityVerlet::step() {
  const int nq = layout_.nq, nz = layout_.nz;
  const double h = step_length();
  double *q = this->q(), *v = this->v(), *z = this->z();
  const double* a = accel();          // a_n now, a_{n+1} after the evaluation below
  const double* zrate = this->zrate();
  // II.25, II.26 and the velocity v* the force sees, block by block with the works' trapezoidal
  // forces times the step's displacement h v_{n+1/2} (with no works the sums are empty).
  auto kick_drift = [&](int begin, int end) {
    for (int k = begin; k < end; ++k) {
      v_half_[k] = v[k] + 0.5 * h * a[k];  // II.25
      q[k] += h * v_half_[k];              // II.26
      v[k] = predicted_ ? v_half_[k] + 0.5 * h * a[k] : v_half_[k];
    }
  };
  work_before(v_half_.data(), h, kick_drift);
  for (int k = 0; k < nz; ++k) {  // one pass: a thermal scene's z holds a temperature per particle
    z_old_[k] = z[k];
    zrate_old_[k] = zrate[k];
    z[k] += h * zrate[k];
  }

  const double t_next = next_time();
  evaluate(t_next, y_, 0);
  // v_{n+1/2} is what the force saw unless it saw the prediction: then one sum serves both. The
  // kick II.27 (a = a_{n+1}) follows each block's sums, which read the velocities it overwrites.
  auto kick = [&](int begin, int end) {
    for (int k = begin; k < end; ++k) v[k] = v_half_[k] + 0.5 * h * a[k];
  };
  work_after(v, predicted_ ? v_half_.data() : v, h, kick);
  // The slope just evaluated is at the predictor z* = z_n + h f_n, not at z_{n+1}. The next step's
  // predictor would reuse it, which is stable only to half the explicit conduction limit (a
  // two-step recurrence, measured on T4: unstable at 0.56 of 2/lambda). The stiff part is linear
  // in z, so f(z_{n+1}) = f(z*) + J (z_{n+1} - z*) exactly: one Jacobian product makes the z
  // update Heun's method, stable to 2/lambda as `kiln check` states. z_{n+1} - z* goes to dz_ in
  // the pass that makes z_{n+1} (dz_ is zero but for its z block: only that block is ever written).
  double* dz = slope_correction_ ? dz_.data() + 2 * nq : nullptr;
#pragma omp parallel for schedule(static) if (parallel_worthwhile(nz))
  for (int k = 0; k < nz; ++k) {
    z[k] = z_old_[k] + 0.5 * h * (zrate_old_[k] + zrate[k]);
    if (dz) dz[k] = 0.5 * h * (zrate[k] - zrate_old_[k]);
  }
  // The works, and the heat the contacts made (book_contact_works), go into z before the slope
  // correction: z_{n+1} - z* includes that heat, so the next step's conduction sees it.
  if (slope_correction_) std::copy_n(z, nz, z_unbooked_.data());
  book_work(z_old_.data(), v_half_.data(), h, 0.5 * h, 0.5 * h);
  if (slope_correction_) {
    for (int k = 0; k < nz; ++k) dz[k] += z[k] - z_unbooked_[k];
    if (!system_->latest_implicit_jacobian_times(dz_.data(), jdz_.data()))
      system_->implicit_jacobian_times(t_next, y_, dz_.data(), jdz_.data());
    for (int k = 0; k < nz; ++k) rate_[2 * nq + k] += jdz_[2 * nq + k];
  }
  advance_time();
  ++stats_.steps;
}

}  // namespace kiln
