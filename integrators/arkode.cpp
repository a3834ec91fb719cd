#include "integrators/arkode.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include <arkode/arkode_butcher.h>
#include <arkode/arkode_butcher_dirk.h>
#include <arkode/arkode_butcher_erk.h>

#include "integrators/vector_kernels.h"
#include "src/base/text_format.h"
#include "src/base/error.h"

namespace kiln {

namespace {

void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string("ARKODE: ") + what + " failed (flag " + std::to_string(flag) + ")");
}

ArkodeIntegrator* self_of(void* p) { return static_cast<ArkodeIntegrator*>(p); }

}  // namespace

// A Butcher table by its SUNDIALS name (without the ARKODE_ prefix), or one of the IMEX Euler pair
// (ARS(1,1,1) [Ascher, Ruuth & Spiteri, Appl. Numer. Math. 25, 1997, sec. 2.1], written with two
// stages on c = (0, 1)): forward Euler on the explicit part, backward Euler on the implicit part.
// Backward Euler keeps the maximum principle of conduction at any step: (C + h L)^-1 C is
// non-negative with rows summing to one, L being a Laplacian (an M-matrix argument).
ARKodeButcherTable load_butcher_table(const std::string& name, bool implicit) {
  ARKodeButcherTable table = nullptr;
  if (name == imex_euler_table) {
    double c[2] = {0, 1};  // SUNDIALS 6.4.1 takes non-const pointers; it copies them
    double forward[4] = {0, 0, 1, 0}, backward[4] = {0, 0, 0, 1};
    double b_forward[2] = {1, 0}, b_backward[2] = {0, 1};
    table = ARKodeButcherTable_Create(2, 1, 0, c, implicit ? backward : forward, implicit ? b_backward : b_forward,
                                      nullptr);
  } else {
    const std::string full = "ARKODE_" + name;
    table = implicit ? ARKodeButcherTable_LoadDIRKByName(full.c_str()) : ARKodeButcherTable_LoadERKByName(full.c_str());
  }
  if (!table) throw std::runtime_error("ARKODE: no Butcher table '" + name + "'");
  return table;
}


ArkodeIntegrator::ArkodeIntegrator(ArkodeMethod method, StepControl control)
    : method_(std::move(method)), control_(control) {}

ArkodeIntegrator::~ArkodeIntegrator() {
  if (memory_) ARKStepFree(&memory_);
  implicit_solver_.reset();
  if (state_) N_VDestroy(state_);
  if (context_) SUNContext_Free(&context_);
}

int ArkodeIntegrator::explicit_rhs(double t, N_Vector y, N_Vector ydot, void* p) {
  ArkodeIntegrator* self = self_of(p);
  if (self->method_.dirk_table.empty())
    self->system_->derivative(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
  else
    self->system_->explicit_part(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
  return 0;
}

int ArkodeIntegrator::implicit_rhs(double t, N_Vector y, N_Vector ydot, void* p) {
  self_of(p)->system_->implicit_part(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
  return 0;
}

void ArkodeIntegrator::start(OdeSystem& system, double t0, double* y, double dt) {
  t_ = grid_start_ = t0;
  grid_steps_ = 0;
  create(system, t0, y, dt, dt);
}

void ArkodeIntegrator::state(SnapshotFields& f) {
  double t_arkode = t_, h = dt_;
  fields(f, t_arkode, h);
}

// ARKODE's own time and its current step, as it holds them (not started: the integrator's own).
void ArkodeIntegrator::fields(SnapshotFields& f, double& t_arkode, double& h) {
  if (f.saving() && memory_) {
    ARKStepGetCurrentTime(memory_, &t_arkode);
    ARKStepGetCurrentStep(memory_, &h);
  }
  f.reals("time", t_, grid_start_, t_arkode, h);
  f.field("grid_steps", grid_steps_);
}

// ARKODE is created anew at the saved state and at its own saved time, so that the stage times it
// passes to the right-hand side are those of the run that saved (fixed steps: bit for bit; its
// first evaluation there is the one that run made at the end of its step).
void ArkodeIntegrator::resume(OdeSystem& system, double* y, double dt, const Snapshot& s, const std::string& p) {
  SnapshotFields f(s, p);
  double t_arkode = 0, h = 0;
  fields(f, t_arkode, h);
  // Fixed steps take their time from the grid (grid_start + k dt), ARKODE from its own: each must
  // be the integrator's time, or the first step would jump the run elsewhere (a changed checkpoint
  // did, past its end). ARKODE's drifts from the grid by its sums' round-off only.
  dt_ = dt;
  const double tol = 1e-6 * dt;
  const bool consistent =
      std::isfinite(t_) && std::isfinite(t_arkode) && std::abs(t_arkode - t_) <= tol && std::isfinite(h) && h > 0 &&
      (control_.rtol > 0 || (grid_steps_ >= 0 && grid_start_ + static_cast<double>(grid_steps_) * dt == t_));
  if (!consistent)
    throw Snapshot::layout_error(f.source(), "holds integrator times that do not agree (" + p + "time: " +
                                                 std::to_string(t_) + " s, ARKODE's " + std::to_string(t_arkode) +
                                                 " s, step " + std::to_string(h) + " s; " + p + "grid_steps " +
                                                 std::to_string(grid_steps_) + " of " + std::to_string(dt) + " s from " +
                                                 std::to_string(grid_start_) + " s)");
  create(system, t_arkode, y, dt, control_.rtol > 0 ? h : dt);
}

void ArkodeIntegrator::create(OdeSystem& system, double t0, double* y, double dt, double h) {
  system_ = &system;
  live_ = y;
  dt_ = dt;
  check(SUNContext_Create(nullptr, &context_), "SUNContext_Create");
  // Contact springs go into the state, so that every stage sees its own elongation, integrated
  // at the table's order (the trapezoid between contact frames is second order at best).
  history_ = system.integrate_history(true);
  system.prepare(t_, y, dt);
  if (history_) full_.assign(y, y + system.layout().size());
  make_state();
  // An IMEX pair on a system without a stiff part (a scene without temperatures) integrates
  // f = f_E + 0: the additive method reduces to its explicit table, which is what runs.
  implicit_ = !method_.dirk_table.empty() && system.has_implicit_part();
  const bool imex = implicit_;
  memory_ = ARKStepCreate(explicit_rhs, imex ? implicit_rhs : nullptr, t0, state_, context_);
  if (!memory_) throw std::runtime_error("ARKODE: ARKStepCreate failed");
  check(ARKStepSetUserData(memory_, this), "SetUserData");
  // ARKODE's own messages off: a failed step becomes kiln's InstabilityError, with its flag name.
  check(ARKStepSetErrFile(memory_, nullptr), "SetErrFile");
  ARKodeButcherTable explicit_table = load_butcher_table(method_.erk_table, false);
  ARKodeButcherTable implicit_table = imex ? load_butcher_table(method_.dirk_table, true) : nullptr;
  const int flag = ARKStepSetTables(memory_, explicit_table->q, explicit_table->p, implicit_table, explicit_table);
  ARKodeButcherTable_Free(explicit_table);
  ARKodeButcherTable_Free(implicit_table);
  check(flag, "SetTables");
  set_tolerances();
  const bool adaptive = control_.rtol > 0;
  if (adaptive) {
    check(ARKStepSetInitStep(memory_, h), "SetInitStep");
  } else {
    check(ARKStepSetFixedStep(memory_, dt), "SetFixedStep");
  }
  check(ARKStepSetMaxNumSteps(memory_, 0), "SetMaxNumSteps");
  // A linear dashpot makes the force jump at a contact's onset: without contact events an adaptive
  // step must shrink until the jump's error is below the tolerance, which at rtol 1e-8 takes more
  // than ARKODE's default 7 successive error-test failures (T5 stopped with ARK_ERR_FAILURE).
  check(ARKStepSetMaxErrTestFails(memory_, 60), "SetMaxErrTestFails");
  if (imex) {
    implicit_solver_ = std::make_unique<ImplicitSolver>(control_.linear_solver, system, state_, context_);
    implicit_solver_->attach(memory_);
    if (system.implicit_part_is_linear()) {
      check(ARKStepSetLinear(memory_, 1), "SetLinear");
    } else {
      // The stage's first Newton iterate has the predictor's positions, so one linear solve leaves
      // an O(h dq) error in the temperatures: second order whatever the pair (measured imex4
      // 2.01 on a disc bouncing on a heated floor). Newton iterates with the conductances of each
      // iterate's positions; the second iterate has the stage's own, the third confirms it.
      check(ARKStepSetNonlinear(memory_), "SetNonlinear");
      check(ARKStepSetMaxNonlinIters(memory_, 6), "SetMaxNonlinIters");
      // Converged when the estimated error is below the tolerance itself (ARKODE's default asks a
      // tenth of it): the stage solves are exact, so what the iteration leaves is round-off, which
      // at a fixed step's 1e-12 a stiff network (gamma lambda ~ 1e3) cannot get a tenth below.
      check(ARKStepSetNonlinConvCoef(memory_, 1.0), "SetNonlinConvCoef");
    }
  }
}

// Tolerances: adaptive runs use the user's; fixed-step runs only stop the implicit iterations
// with them, so they are tight there (the solver error must not hide the truncation error).
void ArkodeIntegrator::set_tolerances() {
  StepControl tol = control_;
  if (!(control_.rtol > 0)) {
    tol.rtol = 1e-12;
    // Temperatures are in Celsius, whose origin is a convention: 1e-12 of one near 0 C plus
    // 1e-14 asked the Newton iteration for 1e-14 K, below the round-off of the heat flows, and an
    // IMEX run starting at 0 C failed at t = 0 blaming dt (issue 28, F13). Unless the user gives
    // one, the temperatures' absolute part is 1e-12 of 0 C in kelvin: the test then weighs
    // 1e-12 of the absolute temperature (or more below 0 C), as a state in kelvin would.
    if (!(tol.atol > 0) && !std::isfinite(tol.atol_temperature)) tol.atol_temperature = tol.rtol * 273.15;
    if (!(tol.atol > 0)) tol.atol = 1e-14;
  } else if (!(tol.atol > 0)) {
    tol.atol = 1e-3 * tol.rtol;
  }
  const std::vector<double> atol = system_->absolute_tolerances(tol);
  N_Vector atol_vector = N_VNew_Serial(static_cast<long>(atol.size()), context_);
  std::copy(atol.begin(), atol.end(), N_VGetArrayPointer(atol_vector));
  const int flag = ARKStepSVtolerances(memory_, tol.rtol, atol_vector);
  N_VDestroy(atol_vector);
  check(flag, "SVtolerances");
}

void ArkodeIntegrator::make_state() {
  const int n = system_->state_size();
  if (history_) {
    const int n_live = system_->layout().size();
    full_.resize(n);
    system_->initial_history(full_.data() + n_live);
    generation_ = system_->history_generation();
  }
  y_ = history_ ? full_.data() : live_;
  scratch_.assign(n, 0.0);
  if (state_) N_VDestroy(state_);
  // The integrator works on the state in place: no copy.
  state_ = N_VMake_Serial(n, y_, context_);
  // Optimised kernels in place of Debian's unoptimised ones (vector_kernels.h); every vector
  // ARKODE clones from the state inherits them.
  use_vector_kernels(state_);
}

// The lists were rebuilt at the state in y_ (prepare(), rebuild_neighbours()): the history
// components are new ones. ARKODE's vectors take their number and its state their values, from
// the step's start; the step size and the error controller's history stay (ARKStepResize), and
// the tolerances and the implicit solver are set again for the new length, as SUNDIALS asks.
void ArkodeIntegrator::follow_history() {
  if (!history_ || system_->history_generation() == generation_) return;
  make_state();
  check(ARKStepResize(memory_, state_, 1.0, t_, nullptr, nullptr), "Resize");
  set_tolerances();
  if (implicit_solver_) implicit_solver_->attach(memory_);
  if (std::isfinite(stop_)) check(ARKStepSetStopTime(memory_, stop_), "SetStopTime");
  ++history_resizes_;
}

void ArkodeIntegrator::set_stop_time(double t) {
  stop_ = t;
  if (control_.rtol > 0) check(ARKStepSetStopTime(memory_, t), "SetStopTime");
}

void ArkodeIntegrator::step() {
  // Neighbour lists are fixed for the whole step: prepare them for the step about to be taken.
  // An adaptive step is first capped at what the lists allow at the current speeds.
  const bool adaptive = control_.rtol > 0;
  double h = dt_;
  if (adaptive) {
    ARKStepGetCurrentStep(memory_, &h);
    const double bound = system_->neighbour_step_bound(y_);
    check(ARKStepSetMaxStep(memory_, std::isfinite(bound) ? bound : 0.0), "SetMaxStep");
    skin_capped_ += bound < h;  // the step the tolerance wanted is longer than the lists allow
    h = std::min(h, bound);
  }
  system_->prepare(t_, y_, h);
  follow_history();
  const double t_start = t_;
  step_start_.assign(y_, y_ + scratch_.size());
  evolve_one_step();
  // A step that outran the lists (its stages may have missed a contact) is redone from its start:
  // a fixed step with lists rebuilt there to cover where it went, an adaptive one halved until
  // it stays inside them (accelerations, not speeds, carried it out).
  for (int redo = 0; !system_->neighbours_cover(t_, y_); ++redo) {
    const double taken = t_ - t_start;
    if (redo == (adaptive ? 30 : 1))
      throw InstabilityError("instability at t = " + std::to_string(t_start) + " s: " +
                             system_->describe_travel(step_start_.data(), y_, taken) +
                             (adaptive ? " even after halving the step " + std::to_string(redo) + " times"
                                       : " even from lists rebuilt for the step") +
                             "; lower dt (or rtol)");
    step_reached_.assign(y_, y_ + scratch_.size());
    std::copy(step_start_.begin(), step_start_.end(), y_);
    t_ = t_start;
    if (adaptive) {
      check(ARKStepSetMaxStep(memory_, 0.5 * taken), "SetMaxStep");
      system_->rebuild_neighbours(t_start, y_, t_start, y_);
    } else {
      system_->rebuild_neighbours(t_start, y_, t_start + taken, step_reached_.data());
    }
    follow_history();
    step_start_.assign(y_, y_ + scratch_.size());
    check(ARKStepReset(memory_, t_start, state_), "Reset");
    if (std::isfinite(stop_)) check(ARKStepSetStopTime(memory_, stop_), "SetStopTime");
    evolve_one_step();
    ++neighbour_redos_;
  }
  if (control_.contact_events && locate_event(t_start)) {
    // A contact started or ended inside the step: the state is now the step retaken from its
    // start to just past that instant. The acting set changes there and the method restarts,
    // so that no stage straddles the kink.
    system_->lock_contacts(t_, y_, flips_.data());
    check(ARKStepReset(memory_, t_, state_), "Reset");
    if (std::isfinite(stop_)) check(ARKStepSetStopTime(memory_, stop_), "SetStopTime");
    ++events_located_;
    // Switches that keep undoing each other at one instant (stick and slip of an element whose
    // event functions disagree at the switch: see contact/stick_slip.h on dashpots) would stall
    // the run at steps of 1e-19 s: stop it, saying so.
    stalled_events_ = t_ - t_start < 1e-9 * dt_ ? stalled_events_ + 1 : 0;
    if (stalled_events_ > 1000)
      throw InstabilityError("contact events at t = " + std::to_string(t_) +
                             " s: 1000 events in a row without the time advancing (stick and slip switching back "
                             "and forth); run without contact_events");
    grid_start_ = t_;  // fixed steps go on from the event
    grid_steps_ = 0;
  } else {
    ++grid_steps_;
    // A fixed step's state is grid_steps_ steps of exactly dt from the grid's start: that is its
    // time, not ARKODE's sum of the steps (which drifts, and used to put a frame one step late).
    if (control_.rtol == 0) t_ = landing_ ? stop_ : grid_start_ + static_cast<double>(grid_steps_) * dt_;
    // A step shortened onto a stop time off the grid starts a new grid there, as an event does:
    // a run resumed from that stop takes whole steps of dt from its state's own time (on the old
    // grid its first step was stamped past the stop by the shortfall, 5.8e-7 s after a located
    // release put the grid off 2e-5 s, with positions 4.9e-8 m off their clock).
    if (control_.rtol == 0 && landing_) {
      grid_start_ = stop_;
      grid_steps_ = 0;
    }
  }
  if (adaptive) {
    // A tolerance that asks for more than double precision gives at a force that jumps (a
    // dashpot's onset, where the velocity's local error falls only as h) shrinks the step until the
    // time cannot take it: rtol 1e-13 ran 40 million steps of 3e-19 s at t = 2.36e-3 s and never
    // ended (issue 28's review). rtol 1e-12 passes the same onset with a few steps of 1.7e-18 s.
    const double round_off = 1e3 * std::numeric_limits<double>::epsilon() * std::max(std::abs(t_), dt_);
    stalled_steps_ = t_ - t_start <= round_off ? stalled_steps_ + 1 : 0;
    if (stalled_steps_ > max_stalled_steps)
      throw InstabilityError("the adaptive step stalled at t = " + format("%.9g", t_) + " s: " +
                             std::to_string(max_stalled_steps) + " steps in a row each advanced the time by less " +
                             "than 1000 of its round-offs (the last " + format("%.3g", t_ - t_start) +
                             " s): rtol and atol ask for more than double precision gives here (a contact force "
                             "that jumps as it starts); loosen rtol (or atol), or locate the onsets (--contact-events)");
  }
  if (system_->has_history()) {
    // The contact history of the accepted step comes from an evaluation at its end (the stages
    // all saw the history committed at the step's start). ARKODE's next first stage evaluates the
    // same state, but it cannot stand in for this one: at the Coulomb cap the capped spring folds
    // the dashpot into the elongation, so an evaluation from the committed history is not the one
    // that made it, and a run's bits would depend on when frames and checkpoints read it.
    system_->prepare(t_, y_, 0);
    system_->derivative(t_, y_, scratch_.data());
    ++history_evals_;
  }
  system_->accept(t_);
  if (history_) std::copy_n(y_, system_->layout().size(), live_);
  refresh_stats();
}

void ArkodeIntegrator::evolve_one_step() {
  if (control_.rtol == 0 && std::isfinite(stop_)) {
    // Fixed steps: ARKODE sums its steps into t, so after many steps its t is off the grid
    // grid_start_ + k dt by their round-off. Which step is the last is decided on the grid; that
    // step is taken from ARKODE's t to exactly the stop time (never a step of 1e-12 s after it).
    // A stop time that is the next grid time up to rounding (a few ulps: 25000 x 2e-6 is
    // 0.049999999999999996, not 0.05) is reached by a whole step of dt, stamped with the grid time
    // (a stop time would cut it to ARKODE's drifted t): a run that ends on the grid takes the steps
    // a longer run takes through it, so that resuming it continues bit for bit. Otherwise the last
    // step is the remainder, ending exactly on the stop time (a truncated dt such as
    // 0.00806451612903 for 0.5/62 leaves 1.6e-13 s, 1400 ulps, which a fifth-order table on F1
    // measures).
    const double remainder = stop_ - (grid_start_ + static_cast<double>(grid_steps_) * dt_);
    const double next_grid = grid_start_ + static_cast<double>(grid_steps_ + 1) * dt_;
    const bool on_grid = std::abs(next_grid - stop_) <= 8 * std::numeric_limits<double>::epsilon() * std::abs(stop_);
    landing_ = remainder <= dt_ * (1 + 1e-9) && !on_grid;
    check(ARKStepSetStopTime(memory_, landing_ ? stop_ : std::numeric_limits<double>::max()), "SetStopTime");
    if (landing_) check(ARKStepSetFixedStep(memory_, stop_ - t_), "SetFixedStep");
  }
  double reached = t_;
  const int flag = ARKStepEvolve(memory_, stop_, state_, &reached, ARK_ONE_STEP);
  if (flag < 0) {
    char* name = ARKStepGetReturnFlagName(flag);
    const std::string text = name ? name : "unknown";
    free(name);
    // The method could not take a step (error test or Newton failures at the smallest step):
    // the run cannot go on, as with a failed stability check.
    throw InstabilityError("ARKODE step failed at t = " + std::to_string(t_) + " s: " + text +
                           "; lower dt (or rtol), or see kiln check for the step the estimate recommends");
  }
  t_ = reached;
}

// Whether any event function turned negative (what the step locked no longer holds); which ones
// go to flips_.
bool ArkodeIntegrator::turned(const std::vector<double>& g) {
  bool any = false;
  flips_.assign(g.size(), 0);
  for (size_t k = 0; k < g.size(); ++k) {
    flips_[k] = g[k] < 0;
    any = any || flips_[k] != 0;
  }
  return any;
}

bool ArkodeIntegrator::locate_event(double t_start) {
  std::vector<double>& g = events_now_;
  g.resize(system_->event_count());
  system_->event_functions(t_, y_, g.data());
  if (!turned(g)) return false;
  // Bisect the step for the first turn. Each trial retakes one step of the method from the
  // step's start, so the state at the event keeps the method's accuracy (an interpolant's would
  // not). Down to 1e-13 of the step: 43 retakes at most.
  double lo = 0, hi = t_ - t_start;
  const double tol = 1e-13 * hi;
  while (hi - lo > tol) {
    const double mid = 0.5 * (lo + hi);
    retake(t_start, mid);
    system_->event_functions(t_start + mid, y_, g.data());
    (turned(g) ? hi : lo) = mid;
  }
  retake(t_start, hi);  // just past the turn
  system_->event_functions(t_start + hi, y_, g.data());
  turned(g);
  t_ = t_start + hi;
  return true;
}

void ArkodeIntegrator::retake(double t_start, double h) {
  std::copy(step_start_.begin(), step_start_.end(), y_);
  check(ARKStepReset(memory_, t_start, state_), "Reset");
  check(ARKStepSetFixedStep(memory_, h), "SetFixedStep");
  double reached = t_start;
  check(ARKStepEvolve(memory_, t_start + h, state_, &reached, ARK_ONE_STEP), "retaking a step");
  // Back to the run's own step control (a fixed step of 0 means adaptive).
  check(ARKStepSetFixedStep(memory_, control_.rtol > 0 ? 0.0 : dt_), "SetFixedStep");
}

void ArkodeIntegrator::refresh_stats() {
  long steps = 0, fe = 0, fi = 0;
  ARKStepGetNumSteps(memory_, &steps);
  ARKStepGetNumRhsEvals(memory_, &fe, &fi);
  stats_.steps = steps;
  stats_.rhs_evals = fe + fi + history_evals_;
  ARKStepGetLastStep(memory_, &stats_.last_step);
}

nlohmann::json ArkodeIntegrator::statistics() const {
  long steps = 0, attempts = 0, fails = 0, fe = 0, fi = 0, newton = 0;
  double last = 0;
  // Not started (a frozen scene's mechanics integrator, saved in its start's checkpoint): no steps
  // yet, and ARKODE would report its missing memory on stderr (as fields() would).
  if (memory_) {
    ARKStepGetNumSteps(memory_, &steps);
    ARKStepGetNumStepAttempts(memory_, &attempts);
    ARKStepGetNumErrTestFails(memory_, &fails);
    ARKStepGetNumRhsEvals(memory_, &fe, &fi);
    ARKStepGetLastStep(memory_, &last);
    if (implicit_) ARKStepGetNumNonlinSolvIters(memory_, &newton);
  }
  nlohmann::json stats = {{"steps", steps},
                          {"attempts", attempts},
                          {"error_test_failures", fails},
                          {"implicit_part", implicit_},
                          {"rhs_evals_explicit", fe},
                          {"rhs_evals_implicit", fi},
                          {"rhs_evals_history", history_evals_},
                          {"springs_in_state", history_},
                          {"state_resizes", history_resizes_},
                          {"newton_iterations", newton},
                          {"last_step", last},
                          {"contact_events", events_located_},
                          {"neighbour_redos", neighbour_redos_},
                          {"steps_capped_by_skin", skin_capped_}};
  if (implicit_solver_) stats.update(implicit_solver_->statistics());
  return stats;
}

}  // namespace kiln
