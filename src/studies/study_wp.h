// `kiln wp`: work-precision, error against cost per integrator (in the manner of DiffEqDevTools'
// WorkPrecisionSet).
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "src/studies/study_ensemble.h"

namespace kiln {

struct WorkPrecisionOptions {
  std::string scene;
  std::vector<std::string> sets;
  std::vector<std::string> integrators;
  std::vector<double> dts;    // fixed steps, or
  std::vector<double> rtols;  // tolerances (adaptive; the first step is the scene's dt)
  std::string quantity;  // empty: default_quantity(scene)
  std::string reference = "analytic";  // analytic | fine | ensemble (set by --seeds)
  // Chaotic scenes (piles, drums): a trajectory has no reference beyond its Lyapunov time, so a
  // scalar quantity is averaged over an ensemble (--seeds) and compared, seed by seed, with the
  // same members run by the first integrator at half the smallest step (or a tenth of the
  // smallest rtol), or with the exact value where the scene has one (--reference analytic).
  double fine_rtol = 1e-11;  // tolerance of the "fine" reference run
  double t_end = 0;
  int repeats = 3;  // timed runs after a warm-up; the minimum wall time is kept
  std::string out_dir;
  int threads = 1;  // timing: one run at a time unless asked otherwise
  bool heat_stage = false;  // vary freeze.integrator and freeze.dt; the settling keeps the scene\'s
  bool quiet = false;
  EnsembleOptions ensemble;
};

nlohmann::json run_work_precision(const WorkPrecisionOptions& options);

}  // namespace kiln
