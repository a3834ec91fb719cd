// What the Verlet schemes share: one right-hand-side evaluation per step, at a state the scheme
// builds, after which the step is accepted (no rejected trial states).
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "integrators/integrator.h"
#include "src/base/parallel.h"

namespace kiln {

class VerletFamily : public Integrator {
 public:
  double time() const override { return t_; }
  void set_stop_time(double t) override { stop_ = t; }
  void state(SnapshotFields& f) override {
    double dt = dt_;  // saved for the record: a resumed run steps at the dt it is given
    f.reals("time", t_, t0_, dt);
    f.field("count", count_);
    f.field("rate", rate_);
    f.field("work_rest", work_rest_);
    carried(f);
  }
  void resume(OdeSystem& system, double* y, double dt, const Snapshot& s, const std::string& p) override {
    start_without_evaluating(system, y, dt);
    SnapshotFields f(s, p);
    state(f);
    // The next step's time comes from the step count (t0 + (n + 1) dt): a count that disagrees
    // with the time would jump the run past its end in one step (a changed checkpoint did, and
    // hung the run in its checkpoint schedule). The time is the grid's, or a stop short of it.
    const double grid = t0_ + static_cast<double>(count_) * dt_;
    if (!(count_ >= 0 && std::isfinite(t0_) && t0_ + static_cast<double>(count_ - 1) * dt_ <= t_ && t_ <= grid))
      throw Snapshot::layout_error(f.source(), "holds a step count (" + p + "count) that does not agree with its time (" +
                                                   p + "time): " + std::to_string(count_) + " steps of " +
                                                   std::to_string(dt_) + " s from t = " + std::to_string(t0_) +
                                                   " s do not end at t = " + std::to_string(t_) + " s");
    stats_.last_step = dt_;
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
  virtual void carried(SnapshotFields&) {}
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
    system.book_contact_works_by_step();
    work_rest_.assign(works_, 0.0);
    work_rest_old_ = work_rest_;
    along_old_ = along_new_ = work_rest_;
  }
  // Binds the system and the live state, and evaluates f(t0, y) into rate_.
  void bind(OdeSystem& system, double t0, double* y, double dt) {
    start_without_evaluating(system, y, dt);
    t_ = t0_ = t0;
    evaluate(t0, y, dt);
    if (works_ > 0) work_after(y + layout_.nq, nullptr, 0);
  }
  // rate_ = f(t, state) with the neighbour lists prepared for it; the step is then accepted.
  void evaluate(double t, const double* state, double lookahead) {
    system_->prepare(t, state, lookahead);
    system_->derivative(t, state, rate_.data());
    system_->accept(t);
    ++stats_.rhs_evals;
  }
  // The works are booked from the system's work forces g (which stay in the system: no copies)
  // along the step's displacement scale * dir: before the step's evaluation with g of the
  // previous one, after it with the new g. Sums in fixed blocks (parallel.h). A scheme may fuse a
  // loop of its step with a sum: `first(begin, end)` runs on each block's indices before its terms
  // are summed (it may write dir there), `then(begin, end)` after them (it may overwrite v): one
  // pass over the state instead of two.
  struct NoLoop {
    void operator()(int, int) const {}
  };
  template <class First = NoLoop>
  void work_before(const double* dir, double scale, First first = {}) {
    const int nq = layout_.nq, works = works_;
    const double* g = nullptr;
    system_->work_components(&g);
    const auto s = fixed_order_sums<3>(nq, sums3_, [&](int begin, int end, double* out) {
      first(begin, end);
      for (int c = 0; c < works; ++c) add_dot(g + c * nq, dir, begin, end, out[c]);
    });
    for (int c = 0; c < works; ++c) along_old_[c] = scale * s[c];
  }
  // After an evaluation at velocities v: what of each work rate is not g . v (e.g. moving walls'
  // part), booked by the z rule; and (dir non-null) the new g along the displacement (one sum
  // when dir is v).
  template <class Then = NoLoop>
  void work_after(const double* v, const double* dir, double scale, Then then = {}) {
    const int nq = layout_.nq, works = works_;
    const double* g = nullptr;
    system_->work_components(&g);
    const bool both = dir && dir != v;
    auto s = fixed_order_sums<6>(nq, sums6_, [&](int begin, int end, double* out) {
      for (int c = 0; c < works; ++c) {
        add_dot(g + c * nq, v, begin, end, out[c]);
        if (both) add_dot(g + c * nq, dir, begin, end, out[3 + c]);
      }
      then(begin, end);
    });
    if (!both)
      for (int c = 0; c < 3; ++c) s[3 + c] = dir ? s[c] : 0.0;
    work_rest_old_.swap(work_rest_);
    for (int c = 0; c < works; ++c) {
      work_rest_[c] = rate_[2 * nq + c] - s[c];
      along_new_[c] = scale * s[3 + c];
    }
  }
  // Sets the work components of z at the step's end: `before` their values at its start,
  // rest_weight_old/new the z rule's weights (times dt) for the rest: the trapezoid
  // 1/2 (g_n + g_n+1) . (q_n+1 - q_n) plus the rest, q_n+1 - q_n = scale * dir as given to
  // work_before() and work_after(). The contact works are added by the same rule.
  void book_work(const double* before, const double* dir, double scale, double rest_weight_old,
                 double rest_weight_new) {
    for (int c = 0; c < works_; ++c)
      z()[c] = before[c] + 0.5 * (along_old_[c] + along_new_[c]) + rest_weight_old * work_rest_old_[c] +
               rest_weight_new * work_rest_[c];
    system_->book_contact_works(dir, scale, rest_weight_old, rest_weight_new, z());
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
  // The system's work components of z: the rest of their rates at the latest and the previous
  // evaluation, and the step's displacement on the previous and the latest work forces.
  int works_ = 0;
  std::vector<double> work_rest_, work_rest_old_;
  std::vector<double> along_old_, along_new_;
  std::vector<std::array<double, 3>> sums3_;  // scratch of the fixed-order sums
  std::vector<std::array<double, 6>> sums6_;
};

}  // namespace kiln
