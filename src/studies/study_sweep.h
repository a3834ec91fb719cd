// `kiln sweep`: time-step sensitivity and the stability boundary of one integrator on a scene.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "src/studies/study_ensemble.h"

namespace kiln {

struct SweepOptions {
  std::string scene;
  std::vector<std::string> sets;
  std::string integrator;
  double dt_min = 0, dt_max = 0;
  int points = 8;                       // dt log-spaced from dt_min to dt_max
  std::vector<std::string> quantities;  // empty: the scene's defaults
  double t_end = 0;
  int bisections = 10;                  // refinements of the stability boundary
  std::string out_dir;
  int threads = 0;
  bool heat_stage = false;  // vary freeze.integrator and freeze.dt; the settling keeps the scene\'s
  bool quiet = false;
  // --seeds: each step an ensemble; its mean's bias against the smallest step's, and the largest
  // step whose bias lies within --tolerance (src/studies/study_ensemble.h)
  EnsembleOptions ensemble;
};

nlohmann::json run_sweep_study(const SweepOptions& options);

}  // namespace kiln
