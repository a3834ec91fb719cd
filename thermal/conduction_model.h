// The conduction law of a pair as a scene gives it: its model and the parameters only some models
// read, with the table (plain data, src/base/model_keys.h) of each model's name and keys that the
// scene reader walks. The laws themselves are thermal/conductance.h.
#pragma once
#include <span>

#include "src/base/model_keys.h"
#include "thermal/conductance.h"

namespace kiln::thermal {

struct ConductionParams {
  ConductionModel model = ConductionModel::lens;
  double conductance = 0;         // constant model: H (W/K)
  double modulus_ratio = 1;       // batchelor_obrien: E_simulated / E_real
  double contact_resistance = 0;  // pipe_network: R_c per unit length (m K/W)
};

using ConductionModelEntry = ModelEntry<ConductionModel, ConductionParams>;

// Every model once, in the order a scene's choices list them.
std::span<const ConductionModelEntry> conduction_models();

}  // namespace kiln::thermal
