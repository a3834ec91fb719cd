// SUNDIALS 6.4.1 ARKODE integrators behind kiln's Integrator interface.
//
// Explicit tables run in ARKStep's explicit-only mode (no implicit table), never in ERKStep:
// ERKStep of 6.4.1 treats every table whose last node is c = 1 as first-same-as-last even when
// the last row of A differs from b (llnl/sundials#311, fixed in 6.7.0), which cuts the order of 9 of
// the 15 tables (../shared/NUMERICS.md). IMEX pairs integrate the system's implicit part (heat
// conduction, linear in the temperatures on a fixed candidate list) with one Newton iteration
// (ARKStepSetLinear) whose linear system ImplicitSolver solves (a sparse Cholesky by default);
// everything else is explicit.
#pragma once
#include <arkode/arkode_arkstep.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <memory>
#include <string>
#include <vector>

#include "integrators/implicit_solver.h"
#include "integrators/integrator.h"

namespace kiln {

// The name standing for either table of the IMEX Euler pair (built in arkode.cpp).
inline constexpr const char* imex_euler_table = "IMEX_EULER";

// A Butcher table by its SUNDIALS name (without the ARKODE_ prefix: ERK tables, or with
// `implicit` DIRK tables) or imex_euler_table; the caller frees it (ARKodeButcherTable_Free).
// Throws std::runtime_error for an unknown name.
ARKodeButcherTable load_butcher_table(const std::string& name, bool implicit);

struct ArkodeMethod {
  std::string erk_table;   // ARKODE name without the prefix, e.g. DORMAND_PRINCE_7_4_5
  std::string dirk_table;  // empty for explicit methods
};

class ArkodeIntegrator final : public Integrator {
 public:
  ArkodeIntegrator(ArkodeMethod method, StepControl control);
  ~ArkodeIntegrator() override;
  void start(OdeSystem& system, double t0, double* y, double dt) override;
  void step() override;
  double time() const override { return t_; }
  void set_stop_time(double t) override;
  nlohmann::json statistics() const override;
  void state(SnapshotFields& f) override;
  void resume(OdeSystem& system, double* y, double dt, const Snapshot& s, const std::string& prefix) override;

 private:
  static int explicit_rhs(double t, N_Vector y, N_Vector ydot, void* self);
  static int implicit_rhs(double t, N_Vector y, N_Vector ydot, void* self);
  // Binds the system and state and creates ARKODE at its time `t_arkode` (the run's time t_ may
  // differ from it by the round-off of ARKODE's summed steps), first step `h`.
  void create(OdeSystem& system, double t_arkode, double* y, double dt, double h);
  // The vector ARKODE advances, over y_ (state_size() components); and, after a rebuild changed
  // the system's history components, that vector resized (ARKStepResize) with the new ones.
  void make_state();
  void follow_history();
  void set_tolerances();
  void fields(SnapshotFields& f, double& t_arkode, double& h);
  void refresh_stats();
  void evolve_one_step();
  bool locate_event(double t_start);
  bool turned(const std::vector<double>& g);
  void retake(double t_start, double h);

  ArkodeMethod method_;
  StepControl control_;
  OdeSystem* system_ = nullptr;
  // The state ARKODE advances: the caller's `live_` itself, or with contact history in the state,
  // `full_` = [caller's state | history], the caller's part copied back after each step.
  double* live_ = nullptr;
  double* y_ = nullptr;
  bool history_ = false;
  std::vector<double> full_;
  long generation_ = 0;        // the system's history_generation() of the state's history
  long history_resizes_ = 0;
  double t_ = 0, dt_ = 0, stop_ = INFINITY;
  double grid_start_ = 0;  // fixed steps: t = grid_start_ + grid_steps_ dt, exactly
  long grid_steps_ = 0;
  bool landing_ = false;   // the step being taken is the last, onto a stop time off the grid
  SUNContext context_ = nullptr;
  N_Vector state_ = nullptr;
  void* memory_ = nullptr;
  std::unique_ptr<ImplicitSolver> implicit_solver_;
  bool implicit_ = false;  // an IMEX pair with a stiff part to solve (false: its explicit table alone)
  std::vector<double> scratch_;  // f at the end of a step, for contact history
  long history_evals_ = 0;
  std::vector<double> events_now_;  // event functions at a trial end (kept: no allocation per step)
  std::vector<int> flips_;       // 1 for each event function that turned at a located event
  std::vector<double> step_start_;  // the state a step started from
  std::vector<double> step_reached_;  // ... and where it went, when it outran the neighbour lists
  long events_located_ = 0;
  long stalled_events_ = 0;  // events in a row located at the step's start
  long stalled_steps_ = 0;   // adaptive steps in a row within the time's round-off (step())
  static constexpr long max_stalled_steps = 10000;
  long neighbour_redos_ = 0;
  long skin_capped_ = 0;  // adaptive steps shortened to the neighbour lists' bound
};

}  // namespace kiln
