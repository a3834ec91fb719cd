// Time-step estimates for a scene, printed by `kiln check` and quoted when a run goes unstable.
#pragma once
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "src/scene/scene.h"

namespace kiln {

// More fixed steps than this would not end in any useful time (a step costs a microsecond at the
// least): refused like an unstable dt (which --force overrides); studies refuse such runs too.
// Adaptive runs are not counted: their dt is only the first guess.
constexpr double max_steps = 1e9;
// The message refusing a stage of `duration` in steps of `step` (named `step_name`) when it has
// more than max_steps steps; nothing otherwise.
std::optional<std::string> too_many_steps(const char* step_name, double step, double duration);

struct StabilityEstimate {
  double contact_duration = INFINITY;  // shortest contact among the pairs the scene can form (s)
  std::string shortest_pair;           // e.g. "copper-copper" or "copper-wall(floor)"
  double rayleigh = INFINITY;          // Rayleigh time of the smallest particle (s); inf without E
  double dt_limit = INFINITY;          // central-difference stability limit of the stiffest contact (s),
                                       // divided by sqrt 2 when a disc can sit between two contacts
  double recommended_dt = INFINITY;    // contact_duration / 50
  double impact_speed = 0;             // highest impact speed for Hertz durations (m/s): two discs meet at
                                       // twice a disc's speed, a disc meets a wall at its own plus the wall's
  // Heat (thermal scenes): explicit stepping of conduction is stable below 2 / lambda_max, lambda_max
  // bounded by Gershgorin on C^-1 L. From the contact network at t = 0, and for a dense packing
  // (six neighbours at 1 % overlap) since contacts form later in dynamic scenes.
  double thermal_dt_limit = INFINITY;          // the smaller of the two (a frozen scene: the network's)
  double thermal_dt_limit_network = INFINITY;  // from the contacts present at t = 0
  double thermal_relaxation_time = INFINITY;   // 1 / lambda_max: the fastest thermal mode
};

StabilityEstimate estimate_stability(const Scene& scene);

// Findings about the scene's dt: warnings (text) and whether dt is certainly unstable.
struct DtVerdict {
  std::vector<std::string> warnings;
  bool unstable = false;
};
DtVerdict judge_dt(const StabilityEstimate& estimate, double dt, const Scene& scene);

}  // namespace kiln
