// `kiln order`: observed orders of integrators on a scene, against an exact solution, a fine
// reference run, or by Richardson's three-level estimate.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "src/scene/scene.h"
#include "src/studies/study_ensemble.h"

namespace kiln {

struct OrderOptions {
  std::string scene;
  std::vector<std::string> sets;
  std::vector<std::string> integrators;
  double dt = 0;        // the coarsest step
  int levels = 4;
  double ratio = 2;     // dt_{k+1} = dt_k / ratio
  std::string quantity;  // empty: default_quantity(scene)
  std::string reference = "analytic";  // analytic | richardson | fine
  double fine_rtol = 1e-11;             // tolerance of the "fine" reference run
  double t_end = 0;     // 0: the scene's
  std::string out_dir;  // order.json, order.csv, order.png
  int threads = 0;      // 0: every core
  bool heat_stage = false;  // vary freeze.integrator and freeze.dt; the settling keeps the scene\'s
  bool quiet = false;
  EnsembleOptions ensemble;  // --seeds: orders of an ensemble mean's bias (src/studies/study_ensemble.h)
};

// Runs the study (in parallel over threads and, under mpirun, ranks; results depend on neither),
// prints the table unless quiet, writes the files if out_dir is given, and returns order.json's
// content.
nlohmann::json run_order_study(const OrderOptions& options);

// With --seeds (study_order_ensemble.cpp): each level an ensemble, its mean's bias against the
// first integrator's ensemble one level below the finest, paired seed by seed; an order between
// two levels only where both biases are detected, with its standard error.
nlohmann::json run_order_ensemble(const OrderOptions& options, const Scene& base, double t_end);
// An integrator's nominal order (0 for a name not in the catalogue).
int nominal_order(const std::string& name);

}  // namespace kiln
