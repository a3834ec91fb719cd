// `kiln order`: observed orders of integrators on a scene, against an exact solution, a fine
// reference run, or by Richardson's three-level estimate.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

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
};

// Runs the study (in parallel over threads and, under mpirun, ranks; results depend on neither),
// prints the table unless quiet, writes the files if out_dir is given, and returns order.json's
// content.
nlohmann::json run_order_study(const OrderOptions& options);

}  // namespace kiln
