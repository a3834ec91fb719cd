// The seam between physics and time stepping. An integrator sees a state vector and a
// right-hand side, never particles. The state is y = [q | v | z]: generalised positions q,
// their velocities v (same length) and first-order quantities z (energy-ledger integrals, later
// temperatures). The right-hand side is f(t, y) = [v | dv/dt | dz/dt].
#pragma once
#include <algorithm>
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "integrators/step_control.h"
#include "src/base/snapshot.h"

namespace kiln {

// The implicit part's Jacobian when it is a diffusion operator on one block of the state:
//   J[block, block] = -W^-1 S   (W > 0 diagonal, S symmetric positive semidefinite, n x n),
//   J[flux, block]  = flux_row  (one component that integrates a flux linear in the block),
// every other entry zero. Conduction: W the heat capacities (J/K), S the conductance Laplacian with
// the wall conductances on its diagonal (W/K), flux the heat from walls. Then
// (I - gamma J) x = b is (W + gamma S) x_block = W b_block, symmetric positive definite.
struct DiffusionJacobian {
  int first = 0;               // the block is y[first, first + n)
  std::vector<double> weight;  // W, n entries
  std::vector<int> row, col;   // S's entries on and below its diagonal (block indices; repeats add)
  std::vector<double> value;
  int flux = -1;               // the flux component, or -1
  std::vector<double> flux_row;  // n entries when flux >= 0

  // Starts over (keeping capacity: no allocation once sized).
  void reset(int first_component, const std::vector<double>& weights, int flux_component) {
    first = first_component;
    weight.assign(weights.begin(), weights.end());
    row.clear();
    col.clear();
    value.clear();
    flux = flux_component;
    flux_row.assign(weights.size(), 0.0);
  }
  // A conductance h between block components i and j, or (j < 0) from i to the outside, whose
  // flux the flux component integrates.
  void add_link(int i, int j, double h) {
    auto add = [&](int r, int c, double v) {
      row.push_back(r);
      col.push_back(c);
      value.push_back(v);
    };
    add(i, i, h);
    if (j >= 0) {
      add(j, j, h);
      add(std::max(i, j), std::min(i, j), -h);
    } else {
      flux_row[i] -= h;
    }
  }
};

struct StateLayout {
  int nq = 0;  // positions (and as many velocities)
  int nz = 0;  // first-order components after the velocities
  int size() const { return 2 * nq + nz; }
};

class OdeSystem {
 public:
  virtual ~OdeSystem() = default;
  virtual StateLayout layout() const = 0;
  // Called once for each new point a step starts evaluating from: (t, y), and how far ahead of t
  // the step may evaluate the right-hand side from these positions (0 when only exactly here).
  // The system may rebuild its neighbour lists here, never inside derivative().
  virtual void prepare(double t, const double* y, double lookahead) = 0;
  // ydot = f(t, y). Must not change anything a later evaluation depends on.
  virtual void derivative(double t, const double* y, double* ydot) = 0;
  // Whether the neighbour lists built in prepare() still cover state y (multi-stage methods check
  // after each step; a step that outran them is redone: fixed steps with lists rebuilt at its start
  // to cover the displacement to `reached`, adaptive ones shorter).
  virtual bool neighbours_cover(double, const double*) const { return true; }
  virtual void rebuild_neighbours(double /*t*/, const double* /*y*/, double /*t_reached*/, const double* /*reached*/) {}
  // The longest step the neighbour lists allow from y at its velocities: adaptive steps are capped
  // at it, so that no stage jumps over a contact the lists do not hold.
  virtual double neighbour_step_bound(const double*) const { return INFINITY; }
  // Why a step from `from` to `to` outran the lists: which particle, how far, how fast, the skin.
  virtual std::string describe_travel(const double* /*from*/, const double* /*to*/, double /*h*/) const { return ""; }
  // The step ending at time t is accepted: contact history from its last evaluation is kept.
  virtual void accept(double t) = 0;
  // True when accept() keeps history that must come from an evaluation at the step's end.
  virtual bool has_history() const { return false; }

  // Contact history in the state. A system whose contacts carry springs may let a multi-stage
  // integrator advance them: after integrate_history(true) returns true, the state is
  // [q | v | z | s], history_size() components s after the layout's, with rates from derivative().
  // Their number and meaning change only when the neighbour lists are rebuilt (prepare(),
  // rebuild_neighbours()), which changes history_generation(): the integrator then resizes its
  // state and takes s from initial_history(), as it does when it starts or resumes.
  virtual bool integrate_history(bool) { return false; }
  virtual int history_size() const { return 0; }
  virtual long history_generation() const { return 0; }
  virtual void initial_history(double*) const {}
  int state_size() const { return layout().size() + history_size(); }

  // IMEX split f = f_E + f_I: f_I is the stiff part, linear in y (heat conduction on a fixed
  // candidate list). Systems without one are fully explicit.
  virtual bool has_implicit_part() const { return false; }
  // Whether f_I is linear in the whole state y (a frozen network). When it also depends on
  // explicit components (conductances on moving positions), a stage's solve is iterated.
  virtual bool implicit_part_is_linear() const { return true; }
  virtual void explicit_part(double t, const double* y, double* ydot) { derivative(t, y, ydot); }
  virtual void implicit_part(double, const double*, double* ydot) { std::fill_n(ydot, state_size(), 0.0); }
  // jv = (d f_I / d y) v.
  virtual void implicit_jacobian_times(double, const double*, const double*, double* jv) {
    std::fill_n(jv, state_size(), 0.0);
  }
  // jv's first-order block (z) = (d f_I / d y) v at the state of the latest derivative() (the
  // implicit part's Jacobian there, from what that evaluation kept: no geometry again); the rest
  // of jv is not touched. False when the system cannot (then implicit_jacobian_times applies).
  virtual bool latest_implicit_jacobian_times(const double*, double*) { return false; }
  // The implicit Jacobian as a diffusion operator (see DiffusionJacobian), at (t, y); false when
  // the implicit part has no such form (then only the matrix-free solver applies).
  virtual bool diffusion_jacobian(double /*t*/, const double* /*y*/, DiffusionJacobian& /*out*/) const { return false; }
  // Contact events. lock_contacts() fixes what the right-hand side holds discontinuous for a step
  // (which contacts act, which springs stick), and event_functions() gives functions that are
  // non-negative while that locked set holds: an event is one turning negative. Their count
  // changes only in prepare(). After a located event `flips` holds 1 for the functions that turned
  // (the system switches what they lock), 0 elsewhere; without flips the system locks from the state.
  virtual int event_count() const { return 0; }
  virtual void event_functions(double, const double*, double*) {}
  virtual void lock_contacts(double, const double*, const int* /*flips*/) {}

  // Work components: the first `count` components of z whose rates are works, of which the part
  // linear in the velocities is g_c . v, g_c a generalized force (nq numbers, laid out as q) from
  // the latest evaluation. A scheme whose force evaluations see an estimated velocity (the Verlet
  // family) books that part as the trapezoid 1/2 (g_c,n + g_c,n+1) . (q_{n+1} - q_n) on its own
  // displacement: the work then matches what the forces did to its trajectory, to second order.
  // Returns count and points g at count x nq numbers (component after component).
  virtual int work_components(const double** /*g*/) const { return 0; }
  // Contact works: further components of z (heat made by dissipation) whose rates are sums over
  // contacts of a work each, linear in the velocities plus a rest. A scheme that books the work
  // components on its displacement calls book_contact_works_by_step() at its start: derivative()
  // then leaves those rates out, and after each step book_contact_works() adds to z each
  // contact's work over the step by the rule of the work components, 1/2 scale (h_n + h_n+1) . dir
  // + rest_weight_old rest_n + rest_weight_new rest_n+1, so that they and the work components
  // agree to round-off.
  virtual void book_contact_works_by_step() {}
  virtual void book_contact_works(const double* /*dir*/, double /*scale*/, double /*rest_weight_old*/,
                                  double /*rest_weight_new*/, double* /*z*/) {}

  // Absolute tolerances per component from the step control (state_size() of them).
  virtual std::vector<double> absolute_tolerances(const StepControl& c) const {
    return std::vector<double>(state_size(), c.atol);
  }
};

struct IntegratorStats {
  long steps = 0;
  long rhs_evals = 0;
  double last_step = 0;  // the length of the latest step taken (s)
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  // Binds the live state `y` (advanced in place by step()) and evaluates what the scheme needs at t0.
  virtual void start(OdeSystem& system, double t0, double* y, double dt) = 0;
  virtual void step() = 0;  // advances y by one step (of the dt given to start(), if fixed)
  virtual double time() const = 0;
  // Adaptive integrators do not step past this time (an output frame, the end).
  virtual void set_stop_time(double) {}
  const IntegratorStats& stats() const { return stats_; }
  // Checkpoints. state() lists, for both directions, what the scheme carries from one step to the
  // next; resume() binds the system and the live state as start() does, but takes that from the
  // snapshot (keys under `prefix`) instead of evaluating anything, so that the steps which follow
  // are those the saving run would have taken (bit for bit with fixed steps; an adaptive ARKODE
  // run goes on from its last step size, with a fresh error-controller history).
  virtual void state(SnapshotFields& f) = 0;
  virtual void resume(OdeSystem& system, double* y, double dt, const Snapshot& s, const std::string& prefix) = 0;
  // Everything the integrator counted, for summary.json's integrator_stats.
  virtual nlohmann::json statistics() const { return {{"steps", stats_.steps}, {"rhs_evals", stats_.rhs_evals}}; }

 protected:
  IntegratorStats stats_;
};

// How an integrator is built: one of the Verlet schemes, or an ARKODE method from its tables.
enum class IntegratorScheme { basic_verlet, velocity_verlet, velocity_verlet_predicted, arkode };

// An integrator's entry in the registry: everything kiln knows of a method, read from here and
// never from its name.
struct IntegratorInfo {
  std::string name;
  std::string alias_of;       // the name this one is short for; empty for a method's own name
  IntegratorScheme scheme = IntegratorScheme::velocity_verlet;
  std::string erk_table, dirk_table;  // arkode: the tables (SUNDIALS names); dirk empty: explicit
  int order = 0;              // nominal order on smooth, velocity-independent forces
  int order_with_dashpot = 0; // order when forces depend on velocity (dashpots, friction)
  int embedding = 0;          // order of the embedded error estimate; 0: none (fixed step only)
  bool implicit = false;      // IMEX: conduction implicit
  bool locates_contact_events = false;  // can lock contacts within a step and locate onsets and releases
  bool integrates_contacts = true;      // false: heat on frozen networks only
  std::string summary;
  // How far the method's stability region reaches along the negative real axis, in units of
  // dt lambda: explicit conduction is stable below dt = real_stability / lambda_max. 2 for forward
  // Euler and Heun (and so for the Verlet schemes' temperatures), 2.51 for third-order and 2.79
  // for fourth-order four-stage tables; infinite for IMEX (conduction implicit).
  double real_stability = 2;
  // How many times a step rounds each position: a far-away scene loses up to half an ulp of its
  // positions at each (the energy check allows for it). The Verlet schemes drift once.
  int position_roundings = 1;
};

// real_stability of the integrator with this name (aliases included); 2 for an unknown name.
double real_stability_of(const std::string& name);

// Every name a user can type, aliases included.
const std::vector<IntegratorInfo>& integrator_catalogue();
// The entry of a name (aliases included); an unknown name throws InputError listing the valid names.
const IntegratorInfo& integrator_info(const std::string& name);
// Creates an integrator by name; an unknown name throws InputError listing the valid names, and
// a step control the method cannot follow (rtol without an embedding, contact events) is refused.
std::unique_ptr<Integrator> make_integrator(const std::string& name, const StepControl& control = {});

}  // namespace kiln
