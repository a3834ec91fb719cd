#include "src/run/stability_guard.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "integrators/integrator.h"
#include "src/base/error.h"

namespace kiln {

namespace {

// A healthy run's ledger error is its integrator's truncation error on the energy that moved, a
// small fraction of it: at most 5.5 % over the test suite (velocity Verlet at the edge of its
// stability on a permanent contact; third-order tables on T1 at 4.4 steps per contact); 4e-6 to
// 2e-4 in T1, T3 and P1 at their own steps. A blow-up makes energy from nothing: the gain grows
// with the kinetic energy, which comes to dominate what is exchanged, so the ratio tends to 1. A
// quarter lies far from both.
constexpr double blow_up_fraction = 0.25;

}  // namespace

StabilityGuard::StabilityGuard(const Scene& scene, const DemSystem& sys, const EnergyLedger& initial,
                               const StabilityEstimate& estimate)
    : scene_(scene), sys_(sys), initial_(initial), estimate_(estimate),
      largest_exchange_(exchanged(initial, initial)) {
  // Far from the origin a step's displacement is rounded to the positions' ulp: a disc 1e5 m up
  // does not move in its first 1 us step (g dt^2 / 2 = 4.9e-12 m is below half an ulp, 7.3e-12 m)
  // while it gains g dt of speed. The potential energy of half an ulp per position per step is
  // what the ledger cannot resolve; the steps taken accumulate it.
  auto half_ulp = [](double x) { return 0.5 * (std::nextafter(std::abs(x), INFINITY) - std::abs(x)); };
  // A step rounds each position as often as its integrator adds to it (ARKODE: once per stage
  // with a weight; the Verlet schemes: once).
  const int roundings = scene.frozen ? 1 : integrator_info(scene.integrator).position_roundings;
  for (int i = 0; i < sys.particles(); ++i)
    rounding_per_step_ += roundings * sys.mass(i) * (std::abs(scene.gravity.x) * half_ulp(scene.position[i].x) +
                                                     std::abs(scene.gravity.y) * half_ulp(scene.position[i].y));
  // Conduction obeys a maximum principle: no temperature leaves the range of the initial and
  // wall temperatures. Heat sources (dissipation turned to heat) only add heat, so with them the
  // lower bound still holds: an unstable conduction mode, which alternates in sign, crosses it.
  if (scene.thermal) {
    low_ = *std::min_element(scene.temperature.begin(), scene.temperature.end());
    high_ = *std::max_element(scene.temperature.begin(), scene.temperature.end());
    for (const Wall& w : scene.walls)
      for (double v : w.temperature.values) {
        low_ = std::min(low_, v);
        high_ = std::max(high_, v);
      }
    width_ = high_ > low_ ? high_ - low_ : 1.0;  // kelvin, when every temperature starts equal
    if (scene.heat_from_dissipation != HeatFromDissipation::none) high_ = INFINITY;
  }
}

void StabilityGuard::every_step(double t, const double* y, double h) {
  ++steps_;
  if (sys_.max_overlap_fraction() > scene_.max_overlap_fraction) {
    std::ostringstream s;
    s << "overlap reached " << sys_.max_overlap_fraction() << " of a radius (limit " << scene_.max_overlap_fraction
      << ", checks.max_overlap_fraction)";
    fail(t, y, s.str());
  }
  // (v h)^2 against r^2 per particle: no division or root in the loop, and no overflow of v^2. The
  // speed after the step stands for the step's: a particle accelerated past its radius in one
  // step is caught at the step that follows.
  // Without walls there is nothing to pass but other particles: what counts is the motion
  // relative to their mean (one disc falling freely alone never passes anything).
  const double *vx = y + sys_.vx_at(), *vy = y + sys_.vy_at();
  double ux = 0, uy = 0;
  if (scene_.segments.empty()) {
    double mass = 0;
    for (int i = 0; i < sys_.particles(); ++i) {
      ux += sys_.mass(i) * vx[i];
      uy += sys_.mass(i) * vy[i];
      mass += sys_.mass(i);
    }
    ux /= mass;
    uy /= mass;
  }
  int fastest = -1;
  double worst = 1;
  for (int i = 0; i < sys_.particles(); ++i) {
    const double dx = (vx[i] - ux) * h, dy = (vy[i] - uy) * h;
    const double travel2 = dx * dx + dy * dy, r2 = sys_.radius(i) * sys_.radius(i);
    if (travel2 > worst * r2) {
      worst = travel2 / r2;
      fastest = i;
    }
  }
  if (fastest >= 0) {
    const double speed = std::hypot(vx[fastest] - ux, vy[fastest] - uy);  // hypot: no overflow
    std::ostringstream s;
    s << "particle " << fastest << " moves " << speed * h << " m in one step (speed " << speed << " m/s"
      << (scene_.segments.empty() ? " relative to the particles' mean" : "") << " x step " << h
      << " s), more than its radius " << sys_.radius(fastest)
      << " m: it can pass through a wall or another particle between two evaluations; at this speed the step must "
         "stay below radius / speed = "
      << sys_.radius(fastest) / speed << " s";
    fail(t, y, s.str());
  }
}

void StabilityGuard::finite(double t, const double* y, int size) {
  for (int k = 0; k < size; ++k)
    if (!std::isfinite(y[k])) fail(t, y, "the state holds NaN or infinity (component " + std::to_string(k) + ")");
  // The ledger too, between frames: a study writes one frame, at its end, which may fall at the
  // apex of a bounce; the largest exchange must have seen the bounce itself.
  energy(t, y, sys_.energy(t, y));
}

void StabilityGuard::temperatures(double t, const double* y) {
  if (!sys_.thermal()) return;
  // Without heat sources no temperature leaves [low, high]. A step that is stable for conduction
  // multiplies each mode of the deviation from the walls' steady state (itself in the range) by
  // |R(z)| <= 1: what a stable run shows beyond the range is modes of either sign adding up,
  // measured at most 2.7 % of the range (P1 under imex4 at 6 times the explicit limit; erk3 and
  // erk4 just below their own limits on F1, 0.6 % and 0.3 %). An inexact implicit solve can throw
  // a step or two beyond the whole range, which the next steps damp (F1, imex4, dt 0.43, with the
  // SPGMR kiln used before, five Krylov vectors: 1.19 widths, then 0.57, 0.06). Growth keeps rising, by |R| > 1
  // per step (forward Euler at 3.5 times its limit: 6). So the run stops when the excursion
  // exceeds a tenth of the width at two successive checks and has grown between them, or at the
  // run's last check, after which nothing can show it shrink; anything less is an accuracy figure.
  // A tenth, not the whole width: a short run must show its growth within a few steps (a sweep of
  // erk4 on T4, three steps a run, puts the boundary at 0.157 s with a tenth, 0.164 s with the
  // whole width, against 0.149 s for RK4's stability interval).
  // The largest excursion with four running maxima in registers (one, through std::max's
  // reference, lived on the stack: a store and a load per particle, 4 % of a thermal step); the
  // particle is looked for only when there is one to name. NaN compares false: finite() names it.
  const double* temps = y + sys_.temperature_at();
  const int n = sys_.particles();
  auto beyond = [&](int i) { return std::max(low_ - temps[i], temps[i] - high_); };
  double most[4] = {0, 0, 0, 0};
  int i = 0;
  for (; i + 4 <= n; i += 4)
    for (int k = 0; k < 4; ++k) {
      const double b = beyond(i + k);
      most[k] = b > most[k] ? b : most[k];
    }
  for (; i < n; ++i) {
    const double b = beyond(i);
    most[0] = b > most[0] ? b : most[0];
  }
  const double excursion = std::max(std::max(most[0], most[1]), std::max(most[2], most[3]));
  int worst = -1;
  if (excursion > 0)
    for (int k = 0; k < n && worst < 0; ++k)
      if (beyond(k) == excursion) worst = k;
  if (excursion > overshoot_) {
    overshoot_ = excursion;
    overshoot_particle_ = worst;
    overshoot_time_ = t;
  }
  const double before = previous_excursion_;
  previous_excursion_ = excursion;
  const double threshold = 0.1 * width_;
  const bool last = t >= scene_.t_end - 1e-9 * dt_;  // as run_scene ends its stages
  const bool growing = before > threshold && excursion > before;
  if (excursion > threshold && (growing || last)) {
    std::ostringstream s;
    s << "temperature of particle " << worst << " is " << y[sys_.temperature_at() + worst]
      << ", beyond the range of the initial and wall temperatures [" << low_ << ", " << high_ << "] by " << excursion
      << " K, more than a tenth of the range's width ";
    if (growing)
      s << "and up from " << before << " K at the previous check";
    else
      s << "at the run's last check";
    s << " (maximum principle of conduction)";
    fail(t, y, s.str());
  }
}

void StabilityGuard::energy(double t, const double* y, const EnergyLedger& now) {
  // The yardstick is the largest exchange so far, not this instant's: at the apex of an elastic
  // bounce the kinetic energy and the potential change are back to zero, and an error of 1e-6 of
  // the bounce read as a blow-up. Both signs count: a dashpot driven unstable books negative
  // dissipation, so the energy it creates shows as a loss in the balance.
  const double error = balance_error(initial_, now);
  // A finite state can still hold energies that overflow (a speed of 1e155 m/s squares to
  // infinity); infinity minus infinity would then pass every comparison below.
  if (!std::isfinite(error) || !std::isfinite(exchanged(initial_, now))) {
    std::ostringstream s;
    s << "energy overflow: the ledger holds a non-finite energy (kinetic " << now.kinetic << " J, potential "
      << now.potential << " J, elastic " << now.elastic << " J)";
    fail(t, y, s.str());
  }
  largest_exchange_ = std::max(largest_exchange_, exchanged(initial_, now));
  if (!(largest_exchange_ > 0)) return;
  const double relative = std::abs(error) / largest_exchange_;
  if (relative > worst_relative_error_) {
    worst_relative_error_ = relative;
    worst_error_time_ = t;
  }
  // Dashpots and friction only take energy out of the motion. A spring mode made unstable by the
  // step can still balance the ledger, through its cap: a tangential spring that grows each step
  // slides at the Coulomb limit, where the booked "dissipation" is the work the slip does, now
  // pumping the disc uphill (a disc at rest on a slope under velocity Verlet at 1.02 times its
  // tangential-rotational limit books -7.6e-10 J of friction by t = 0.09 s, as much as the 7.5e-10 J
  // it started with). A healthy run's
  // dissipation dips below zero by its truncation error at most.
  const double dissipated = now.dissipated_damping - initial_.dissipated_damping + now.dissipated_friction -
                            initial_.dissipated_friction;
  if (-dissipated > blow_up_fraction * largest_exchange_) {
    std::ostringstream s;
    s << "dissipation went negative: the dashpots and friction have put " << -dissipated
      << " J into the motion (damping " << now.dissipated_damping - initial_.dissipated_damping << " J, friction "
      << now.dissipated_friction - initial_.dissipated_friction << " J), more than " << blow_up_fraction
      << " of the largest energy exchanged so far (" << largest_exchange_ << " J)";
    fail(t, y, s.str());
  }
  const double rounding = rounding_per_step_ * static_cast<double>(steps_);
  if (std::abs(error) > blow_up_fraction * largest_exchange_ + rounding) {
    std::ostringstream s;
    s << "energy blow-up: the ledger is off by " << error << " J, more than " << blow_up_fraction
      << " of the largest energy exchanged so far (" << largest_exchange_ << " J) plus the positions' round-off ("
      << rounding << " J)";
    fail(t, y, s.str(), true);
  }
}

nlohmann::json StabilityGuard::figures() const {
  nlohmann::json f = {{"energy_balance",
                       {{"largest_exchange", largest_exchange_},
                        {"worst_relative_error", worst_relative_error_},
                        {"worst_at", worst_error_time_},
                        {"blow_up_above", blow_up_fraction},
                        {"round_off_allowance", rounding_per_step_ * static_cast<double>(steps_)}}}};
  if (sys_.thermal()) {
    const double width = width_;
    const bool any = overshoot_particle_ >= 0;
    f["max_principle_overshoot"] = {{"kelvin", overshoot_},
                                    {"fraction_of_range", overshoot_ / width},
                                    {"particle", any ? nlohmann::json(overshoot_particle_) : nlohmann::json(nullptr)},
                                    {"time", any ? nlohmann::json(overshoot_time_) : nlohmann::json(nullptr)},
                                    {"range", {low_, high_}}};
  }
  return f;
}

void StabilityGuard::fail(double t, const double* y, const std::string& what, bool made_energy) const {
  std::ostringstream s;
  s << "unstable run at t = " << t << " s: " << what << ". dt = " << dt_ << " s; ";
  if (std::isinf(heat_limit_)) {
    s << "conduction is implicit here: no step limit applies (an inexact stage solve?)";
  } else if (!std::isnan(heat_limit_)) {
    s << "explicit conduction of this network is stable below dt = " << heat_limit_
      << " s with this integrator (IMEX integrators, imex1 and imex3 to imex5, have no such limit)";
  } else {
    // The contacts now may bind below those at the start (a pile that formed): the limit on them
    // joins the start's.
    const std::optional<MechanicalLimit> now =
        limit_at(sys_, t, y, sys_.layout().size(), estimate_.integrator);
    const StabilityEstimate est = now ? with_state(estimate_, *now) : estimate_;
    // A step already within the recommendation is not what failed: "recommends dt <= 7.2e117 s"
    // was the advice to a run of dt 1e-5 whose discs, of Young's modulus 1e-300, passed through
    // each other (issue 28's review).
    // Explicit conduction beyond its limit is a cause the recommendation does not cover (its dense
    // packing's limit too: contacts that formed since the start).
    const double reach = real_stability_of(est.integrator) / 2;
    const double conduction = reach * est.thermal_dt_limit_network, packed = reach * est.thermal_dt_limit;
    if (est.recommended_dt >= dt_ && !(dt_ >= conduction) && !(dt_ >= packed)) {
      s << "this dt is within what the stability estimate recommends (" << est.recommended_dt << " s; "
        << describe_limit(est) << "), so the step is not the cause: an overlap that grows at a resolved step "
        << "means contacts too soft for the loads on them (raise the stiffness or Young's modulus), a speed that "
        << "grows means forces or loads beyond what the scene intends";
      throw InstabilityError(s.str());
    }
    s << "the stability estimate recommends dt <= " << est.recommended_dt
      << (est.recommended_dt < est.contact_duration / 50 ? " s (the stability limit; contact duration "
                                                          : " s (contact duration ")
      << est.contact_duration << " s / 50, " << est.shortest_pair << "; " << describe_limit(est);
    if (std::isfinite(conduction)) s << "; explicit conduction limit " << conduction << " s on the network at t = 0";
    if (std::isfinite(packed) && !(packed >= dt_))
      s << "; explicit conduction limit " << packed << " s on a dense packing at 1 % overlap, below this dt";
    s << ")";
    if (est.dt_limit > dt_ && est.dt_limit == estimate_.dt_limit && !now)
      s << "; the state at this failure is not finite, so the limit is the start's, above this dt: a contact network "
           "formed since can bind lower (kiln sweep measures the limit on a settled end state)";
    else if (est.dt_limit > dt_)
      s << "; that limit is above this dt: the contacts at this failure (a state already blown apart) do not show "
           "the network that failed; a settled network can bind lower (kiln sweep measures the limit on its end state)";
    // Or no linear mode grew, and what made the energy is the switching of contact forces: a disc
    // at rest on a floor under ARK437L2SA at 0.86 of its limit (0.78 steps per contact) gains
    // energy from stages that leave the contact; started 500 times closer to its rest overlap it
    // runs to 0.99 of the limit and stops at 1.02 (tests/run/stability_limit_test.cpp).
    if (made_energy && est.dt_limit > dt_ && est.contact_duration < under_resolved_contact * dt_) {
      std::ostringstream steps;
      steps.precision(3);
      steps << est.contact_duration / dt_;
      s << ". Or no linear mode grew: a contact lasts only " << steps.str()
        << " steps here, so its onset and release fall inside steps, where an evaluation meets a force that "
           "switches on or off, and the energy that makes is not bounded by the linear limit; the recommended "
           "dt resolves the contacts";
    }
  }
  throw InstabilityError(s.str());
}

void StabilityGuard::state(SnapshotFields& f) {
  f.reals("measured", largest_exchange_, worst_relative_error_, worst_error_time_, overshoot_, overshoot_time_,
          previous_excursion_);
  f.integers("counts", steps_, overshoot_particle_);
}

}  // namespace kiln
