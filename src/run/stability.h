// Time-step estimates for a scene, printed by `kiln check` and quoted when a run goes unstable.
#pragma once
#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "src/scene/scene.h"

namespace kiln {

// More fixed steps than this would not end in any useful time (a step costs a microsecond at the
// least): refused like an unstable dt (which --force overrides); studies refuse such runs too.
// Adaptive runs are not counted: their dt is only the first guess.
constexpr double max_steps = 1e9;
// The message refusing a stage of `duration` (named `duration_name`) in steps of `step` (named
// `step_name`) when it has more than max_steps steps; nothing otherwise.
std::optional<std::string> too_many_steps(const char* step_name, double step, double duration,
                                          const char* duration_name = "t_end");
// The same for the moving stage of a scene at step dt run to t_end: until t_end, or until
// freeze.latest when the scene freezes before (N2's settling at 1e-6 s is 1e5 steps, not 1.8e9).
std::optional<std::string> too_many_moving_steps(const Scene& scene, double dt, double t_end);

// An integrator's step limit on the linearised mechanics of one state of a scene
// (src/run/linearised_dynamics.h, integrators/stability_region.h), and the mode that binds it.
struct MechanicalLimit {
  double dt = INFINITY;    // the largest stable step (s); inf: no spring or dashpot limits it
  std::string mode;        // "normal", "tangential-rotational", "rolling", "wall body"
  std::string where;       // "particles 3 and 7", "particle 0 on wall floor", "wall lid"
  std::string state;       // the state analysed: "the contacts at t = 0", "a lone copper-copper contact"
  double omega_max = 0;    // that state's stiffest undamped frequency (rad/s)
  // When a tangential-rotational or rolling mode binds a Verlet scheme, the limit of the modes no
  // cap bounds (normal, wall body; linearise_mechanics' Springs::uncapped), where the run blows
  // up: between the two a sticking contact is not resolved, its mode grows to the Coulomb or
  // rolling cap and the contact creeps or chatters there (a disc on a slope slides down it), and
  // only just beyond the first does the dissipation check stop it. Equal to dt otherwise (the
  // Runge-Kutta tables blow up at the limit itself).
  double blow_up_dt = INFINITY;
  int coordinates = 0, contacts = 0;
};

class DemSystem;
// The limit of `integrator` on the contacts of `system` in state y at time t (its lists
// prepared there), described as `state`.
MechanicalLimit mechanical_limit(const DemSystem& system, double t, const double* y, const std::string& integrator,
                                 const std::string& state);

struct StabilityEstimate {
  double contact_duration = INFINITY;  // shortest contact among the pairs the scene can form (s)
  std::string shortest_pair;           // e.g. "copper-copper" or "copper-wall(floor)"
  double rayleigh = INFINITY;          // Rayleigh time of the smallest particle (s); inf without E
  // The integrator's limit: the smaller of the contacts present at t = 0 and, for contacts that
  // form later, each pair of materials (and each material with each wall) touching alone at its
  // impact overlap. Contacts that form a network later (a pile) can bind below it.
  std::string integrator;              // whose limit
  MechanicalLimit limit;
  double dt_limit = INFINITY;          // limit.dt (s)
  double recommended_dt = INFINITY;    // contact_duration / 50, at most the limit
  double impact_speed = 0;             // highest impact speed for Hertz durations (m/s): two discs meet at
                                       // twice a disc's speed, a disc meets a wall at its own plus the wall's
  // Heat (thermal scenes): explicit stepping of conduction is stable below 2 / lambda_max, lambda_max
  // the largest eigenvalue of C^-1 L (FrozenConduction::stiffest_rate). From the contact network
  // at t = 0, and for a dense packing (a triangular lattice at 1 % overlap) since contacts form
  // later in dynamic scenes.
  double thermal_dt_limit = INFINITY;          // the smaller of the two (a frozen scene: the network's)
  double thermal_dt_limit_network = INFINITY;  // from the contacts present at t = 0
  double thermal_relaxation_time = INFINITY;   // 1 / lambda_max: the fastest thermal mode
  // The integrator's own explicit conduction limit on the network at t = 0: its reach on the
  // negative real axis / lambda_max (inf when it takes conduction implicitly).
  double conduction_dt_limit = INFINITY;
  double seconds = 0;  // wall time the estimate took (s): a run's start-up, not its steps
};

// The estimate for `integrator` (empty: the scene's; a frozen scene's heat stage: freeze.integrator's).
StabilityEstimate estimate_stability(const Scene& scene, const std::string& integrator = "");

// The estimate with the limit on another state of the scene (a settled pile, a run's state when a
// check fired: its contact network, which the start may not have) where that binds lower, and
// the recommended dt clipped to it.
StabilityEstimate with_state(StabilityEstimate estimate, const MechanicalLimit& at_state);
// The integrator's limit on the contacts of `system` (its lists prepared near y) in state y at
// time t, described as "the contacts at t = <t> s<what>"; nothing when y is not finite or the
// linearisation fails (a state blown apart).
std::optional<MechanicalLimit> limit_at(const DemSystem& system, double t, const double* y, int size,
                                        const std::string& integrator, const std::string& what = "");

// "erk4's limit 5.84e-4 s on the contacts at t = 0 (tangential-rotational mode, particle 0 on
// wall floor)", or why there is none.
std::string describe_limit(const StabilityEstimate& estimate);
// A limit as JSON (dt_limit, binding_mode, binding_where, state, omega_max, coordinates,
// contacts, blow_up_dt_limit), and back.
nlohmann::json limit_json(const MechanicalLimit& limit);
MechanicalLimit limit_of_json(const nlohmann::json& j);
// The estimate as summary.json, `kiln check --json` and `kiln sweep` write it.
nlohmann::json estimate_json(const StabilityEstimate& estimate);

// Findings about the scene's dt: warnings (text) and whether dt is certainly unstable.
struct DtVerdict {
  std::vector<std::string> warnings;
  bool unstable = false;
};
DtVerdict judge_dt(const StabilityEstimate& estimate, double dt, const Scene& scene);

}  // namespace kiln
