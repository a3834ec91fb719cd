// What the Verlet schemes share: one right-hand-side evaluation per step, at a state the scheme
// builds, after which the step is accepted (no rejected trial states).
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "integrators/integrator.h"

namespace kiln {

class VerletFamily : public Integrator {
 public:
  double time() const override { return t_; }
  void set_stop_time(double t) override { stop_ = t; }
  void save(Snapshot& s, const std::string& p) const override {
    s.put(p + "time", {t_, t0_, dt_});
    s.put_integer(p + "count", count_);
    s.put(p + "rate", rate_);
    s.put(p + "work_force", work_force_);
    s.put(p + "work_force_old", work_force_old_);
    s.put(p + "work_rest", work_rest_);
    s.put(p + "work_rest_old", work_rest_old_);
    save_carried(s, p);
  }
  void resume(OdeSystem& system, double* y, double dt, const Snapshot& s, const std::string& p) override {
    start_without_evaluating(system, y, dt);
    const std::vector<double>& time = s.reals(p + "time");
    t_ = time.at(0);
    t0_ = time.at(1);
    count_ = s.integer(p + "count");
    stats_.last_step = dt_;
    rate_ = s.reals(p + "rate");
    work_force_ = s.reals(p + "work_force");
    work_force_old_ = s.reals(p + "work_force_old");
    work_rest_ = s.reals(p + "work_rest");
    work_rest_old_ = s.reals(p + "work_rest_old");
    resume_carried(s, p);
  }

 protected:
  // t_n = t_0 + n dt: no drift from summing dt. The step that would pass the stop time ends on it
  // instead (a run's last step, when t_end is not a multiple of dt). Within 1e-9 dt it is a whole
  // step of dt, stamped with its grid time (0.049999999999999996 for 25000 steps of 2e-6 s, not the
  // 0.05 asked): the step and the time a longer run has there, so that a resumed run continues bit
  // for bit, time stamps included.
  bool lands_on_stop() const { return t0_ + static_cast<double>(count_ + 1) * dt_ > stop_ - 1e-9 * dt_; }
  double next_time() const { return step_length() < dt_ ? stop_ : t0_ + static_cast<double>(count_ + 1) * dt_; }
  // The length of the step about to be taken: dt, or the shorter remainder to the stop time.
  double step_length() const { return lands_on_stop() && stop_ - t_ < dt_ * (1 - 1e-9) ? stop_ - t_ : dt_; }
  void advance_time() {
    const double t_next = next_time();
    stats_.last_step = step_length();
    t_ = t_next;
    ++count_;
  }

  // What a scheme of the family carries between steps beyond the shared state (for checkpoints).
  virtual void save_carried(Snapshot&, const std::string&) const {}
  virtual void resume_carried(const Snapshot&, const std::string&) {}
  // Binds the system and the live state and sizes every array (start() and resume()).
  virtual void start_without_evaluating(OdeSystem& system, double* y, double dt) {
    system_ = &system;
    layout_ = system.layout();
    y_ = y;
    count_ = 0;
    dt_ = dt;
    rate_.assign(layout_.size(), 0);
    const double* g = nullptr;
    works_ = system.work_components(&g);
    work_force_.assign(works_ * layout_.nq, 0.0);
    work_force_old_ = work_force_;
    work_rest_.assign(works_, 0.0);
    work_rest_old_ = work_rest_;
  }
  // Binds the system and the live state, and evaluates f(t0, y) into rate_.
  void bind(OdeSystem& system, double t0, double* y, double dt) {
    start_without_evaluating(system, y, dt);
    t_ = t0_ = t0;
    evaluate(t0, y, dt);
    work_force_old_ = work_force_;
    work_rest_old_ = work_rest_;
  }
  // rate_ = f(t, state) with the neighbour lists prepared for it; the step is then accepted.
  void evaluate(double t, const double* state, double lookahead) {
    system_->prepare(t, state, lookahead);
    system_->derivative(t, state, rate_.data());
    system_->accept(t);
    ++stats_.rhs_evals;
    if (works_ == 0) return;
    const int nq = layout_.nq;
    const double* g = nullptr;
    system_->work_components(&g);
    work_force_old_.swap(work_force_);
    work_rest_old_.swap(work_rest_);
    std::copy_n(g, works_ * nq, work_force_.data());
    // What of each work rate is not g . v (e.g. moving walls' part): booked by the z rule.
    for (int c = 0; c < works_; ++c) {
      double linear = 0;
      for (int k = 0; k < nq; ++k) linear += g[c * nq + k] * state[nq + k];
      work_rest_[c] = rate_[2 * nq + c] - linear;
    }
  }
  // Sets the work components of z at the step's end: `before` their values at its start, dq the
  // step's displacement, rest_weight_old/new the z rule's weights (times dt) for the rest.
  void book_work(const double* before, const double* dq, double rest_weight_old, double rest_weight_new) {
    const int nq = layout_.nq;
    for (int c = 0; c < works_; ++c) {
      double w = 0;
      for (int k = 0; k < nq; ++k) w += 0.5 * (work_force_old_[c * nq + k] + work_force_[c * nq + k]) * dq[k];
      z()[c] = before[c] + w + rest_weight_old * work_rest_old_[c] + rest_weight_new * work_rest_[c];
    }
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
  double stop_ = INFINITY;
  long count_ = 0;
  std::vector<double> rate_;  // f at the latest evaluation
  // The system's work components of z, their generalized forces at the latest and the previous
  // evaluation, and the rest of their rates there.
  int works_ = 0;
  std::vector<double> work_force_, work_force_old_;
  std::vector<double> work_rest_, work_rest_old_;
};

}  // namespace kiln
