// The exact temperatures of a frozen conduction network with isothermal walls at constant
// temperatures: C dT/dt = -K T + b, K the conductance Laplacian with the wall conductances on its
// diagonal, b_i = sum_w H_iw T_w. With u = C^(1/2) T and A = C^(-1/2) K C^(-1/2) = V diag(l) V^T,
// each mode w_k = (V^T u)_k follows w_k(t) = w_k(0) e^(-l_k t) + beta_k (1 - e^(-l_k t)) / l_k
// (beta_k t for l_k = 0), beta = V^T C^(-1/2) b: exact up to the eigen-solver's round-off.
// Dense (O(n^3)): networks of a few thousand particles.
#pragma once
#include <vector>

#include "src/dem/dem_system.h"

namespace kiln::thermal {

// links: particle pairs (j >= 0) and wall links (j = -1 - wall); capacity: m c_p per particle (J/K);
// wall_temperature: per wall (C or K); initial: T at t = 0. Returns T at time t.
std::vector<double> exact_network_temperatures(const std::vector<ConductanceLink>& links,
                                               const std::vector<double>& capacity,
                                               const std::vector<double>& wall_temperature,
                                               const std::vector<double>& initial, double t);

}  // namespace kiln::thermal
