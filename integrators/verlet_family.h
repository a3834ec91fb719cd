// What the Verlet schemes share: one right-hand-side evaluation per step, at a state the scheme
// builds, after which the step is accepted (no rejected trial states).
#pragma once
#include <vector>

#include "integrators/integrator.h"

namespace kiln {

class VerletFamily : public Integrator {
 public:
  double time() const override { return t_; }

 protected:
  // t_n = t_0 + n dt: no drift from summing dt.
  double next_time() const { return t0_ + static_cast<double>(count_ + 1) * dt_; }
  void advance_time() { t_ = t0_ + static_cast<double>(++count_) * dt_; }

  // Binds the system and the live state, and evaluates f(t0, y) into rate_.
  void bind(OdeSystem& system, double t0, double* y, double dt) {
    system_ = &system;
    layout_ = system.layout();
    y_ = y;
    t_ = t0_ = t0;
    count_ = 0;
    dt_ = dt;
    rate_.assign(layout_.size(), 0);
    evaluate(t0, y, dt);
  }
  // rate_ = f(t, state) with the neighbour lists prepared for it; the step is then accepted.
  void evaluate(double t, const double* state, double lookahead) {
    system_->prepare(t, state, lookahead);
    system_->derivative(t, state, rate_.data());
    system_->accept(t);
    ++stats_.rhs_evals;
  }

  // Views of the live state y = [q | v | z] and of the latest rates [v | a | dz/dt].
  double* q() const { return y_; }
  double* v() const { return y_ + layout_.nq; }
  double* z() const { return y_ + 2 * layout_.nq; }
  const double* accel() const { return rate_.data() + layout_.nq; }
  const double* zrate() const { return rate_.data() + 2 * layout_.nq; }

  OdeSystem* system_ = nullptr;
  StateLayout layout_;
  double* y_ = nullptr;
  double t_ = 0, t0_ = 0, dt_ = 0;
  long count_ = 0;
  std::vector<double> rate_;  // f at the latest evaluation
};

}  // namespace kiln
