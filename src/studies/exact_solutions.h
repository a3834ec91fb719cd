// Exact solutions registered for standard cases, the references of `kiln order --reference
// analytic` and of the verification matrix (tests/studies/verification_matrix.tsv). Each gives the exact
// value at time t of a quantity the run reports: closed forms piece by piece for one disc on a
// floor (T1, the harmonic contact; with Coulomb friction the 2/7 stick impact, the oblique impact
// in gross sliding, slide to roll and C1 rolling), eigen-decompositions for frozen conduction.
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "src/scene/scene.h"

namespace kiln {

// The exact quantity of `scene` at time t, or nothing if no solution is registered for the
// scene's case and quantity. Quantities: "position" (x then y of every particle), "velocity",
// "temperature", or a summary scalar such as "incline_acceleration".
std::optional<std::vector<double>> exact_quantity(const Scene& scene, const std::string& quantity, double t);

// The cases and quantities that have one, for messages.
std::string exact_solutions_known();

}  // namespace kiln
