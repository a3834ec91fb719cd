#include "src/dem/frozen_conduction.h"

#include <algorithm>

#include "src/base/symmetric_eigen.h"

namespace kiln::thermal {

FrozenConduction::FrozenConduction(std::vector<ConductanceLink> links, std::vector<double> capacity,
                                   std::vector<WallTemperature> walls, int ledger_entries)
    : links_(std::move(links)), walls_(std::move(walls)), ledger_(ledger_entries) {
  for (double c : capacity) inv_capacity_.push_back(1 / c);
  capacity_ = std::move(capacity);
}

void FrozenConduction::conduct(double t, const double* temp, double* zdot, bool walls) const {
  const int n = static_cast<int>(inv_capacity_.size());
  std::fill_n(zdot, ledger_ + n, 0.0);
  double* heat = zdot + ledger_;
  double from_walls = 0;
  for (const ConductanceLink& link : links_) {
    if (link.j >= 0) {
      const double q = link.h * (temp[link.j] - temp[link.i]);
      heat[link.i] += q;
      heat[link.j] -= q;
    } else {
      const double q = link.h * ((walls ? walls_[-1 - link.j].at(t) : 0.0) - temp[link.i]);
      heat[link.i] += q;
      from_walls += q;
    }
  }
  for (int i = 0; i < n; ++i) heat[i] *= inv_capacity_[i];
  // Without the walls' temperatures this is the Jacobian's row of the heat from walls: -sum h T_i.
  zdot[ledger_heat_walls] = from_walls;
}

bool FrozenConduction::diffusion_jacobian(double, const double*, DiffusionJacobian& out) const {
  out.reset(ledger_, capacity_, ledger_heat_walls);
  for (const ConductanceLink& link : links_) out.add_link(link.i, link.j, link.h);  // wall links have j < 0
  return true;
}

FrozenConduction freeze_network(const DemSystem& system, double t, const double* y) {
  std::vector<WallTemperature> walls;
  for (const Wall& w : system.scene().walls) walls.push_back(w.temperature);
  std::vector<double> capacity;
  for (int i = 0; i < system.particles(); ++i) capacity.push_back(system.heat_capacity(i));
  return FrozenConduction(system.conduction_links(t, y), capacity, walls, system.ledger_count());
}

double FrozenConduction::stiffest_rate() const {
  // C^-1 L is similar to the symmetric C^-1/2 L C^-1/2: the same eigenvalues, found from that.
  std::vector<Eigen::Triplet<double>> entries;
  auto add = [&](int a, int b, double h) {
    // Each root taken alone: the product of two inverse capacities near 1e300 overflows.
    entries.emplace_back(a, b, h * std::sqrt(inv_capacity_[a]) * std::sqrt(inv_capacity_[b]));
  };
  for (const ConductanceLink& link : links_) {
    add(link.i, link.i, link.h);
    if (link.j < 0) continue;  // a wall: its conductance on the diagonal alone
    add(link.j, link.j, link.h);
    add(link.i, link.j, -link.h);
    add(link.j, link.i, -link.h);
  }
  const int n = static_cast<int>(inv_capacity_.size());
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(entries.begin(), entries.end());
  if (a.nonZeros() == 0) return 0;
  // NaN (an overflowed conductance or capacity) is returned as such: max(0, NaN) read it as 0, "no
  // conducting contact", and the run died of NaN.
  const double rate = largest_eigenpairs(a, 1).values[0];
  return std::isnan(rate) ? rate : std::max(0.0, rate);
}

}  // namespace kiln::thermal
