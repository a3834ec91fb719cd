// Integrators by name: the names a user types (`--integrator`, the scene's `integrator:` key).
#include <memory>

#include "integrators/integrator.h"
#include "integrators/velocity_verlet.h"
#include "integrators/verlet.h"
#include "src/error.h"
#include "src/nearest.h"

namespace kiln {

const std::vector<IntegratorInfo>& integrator_catalogue() {
  static const std::vector<IntegratorInfo> catalogue = {
      {"verlet", 2, 1, "basic Stormer-Verlet (thesis II.16, II.20, II.21); backward-difference velocity in forces"},
      {"velocity-verlet", 2, 1, "velocity Verlet (thesis II.25-II.27); half-step velocity in forces, as LAMMPS"},
      {"velocity-verlet-predicted", 2, 2, "velocity Verlet with the predicted v_n + a_n dt in forces"},
  };
  return catalogue;
}

std::unique_ptr<Integrator> make_integrator(const std::string& name) {
  if (name == "verlet") return std::make_unique<BasicVerlet>();
  if (name == "velocity-verlet") return std::make_unique<VelocityVerlet>(false);
  if (name == "velocity-verlet-predicted") return std::make_unique<VelocityVerlet>(true);
  std::vector<std::string> names;
  for (const auto& info : integrator_catalogue()) names.push_back(info.name);
  throw InputError("unknown integrator '" + name + "'; valid names are " + choices_nearest_first(name, names));
}

}  // namespace kiln
