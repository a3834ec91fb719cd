// The seam between physics and time stepping. An integrator sees a state vector and a
// right-hand side, never particles. The state is y = [q | v | z]: generalised positions q,
// their velocities v (same length) and first-order quantities z (energy-ledger integrals, later
// temperatures). The right-hand side is f(t, y) = [v | dv/dt | dz/dt].
#pragma once
#include <memory>
#include <string>
#include <vector>

namespace kiln {

struct StateLayout {
  int nq = 0;  // positions (and as many velocities)
  int nz = 0;  // first-order components after the velocities
  int size() const { return 2 * nq + nz; }
};

class OdeSystem {
 public:
  virtual ~OdeSystem() = default;
  virtual StateLayout layout() const = 0;
  // Called once for each new point a step starts evaluating from: (t, y), and how far ahead of t
  // the step may evaluate the right-hand side from these positions (0 when only exactly here).
  // The system may rebuild its neighbour lists here, never inside derivative().
  virtual void prepare(double t, const double* y, double lookahead) = 0;
  // ydot = f(t, y). Must not change anything a later evaluation depends on.
  virtual void derivative(double t, const double* y, double* ydot) = 0;
  // The step ending at time t is accepted: contact history from its last evaluation is kept.
  virtual void accept(double t) = 0;
};

struct IntegratorStats {
  long steps = 0;
  long rhs_evals = 0;
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  // Binds the live state `y` (advanced in place by step()) and evaluates what the scheme needs at t0.
  virtual void start(OdeSystem& system, double t0, double* y, double dt) = 0;
  virtual void step() = 0;  // advances y by one step of the dt given to start()
  virtual double time() const = 0;
  const IntegratorStats& stats() const { return stats_; }

 protected:
  IntegratorStats stats_;
};

struct IntegratorInfo {
  std::string name;
  int order = 0;              // nominal order on smooth, velocity-independent forces
  int order_with_dashpot = 0; // order when forces depend on velocity (dashpots, friction)
  std::string summary;
};

const std::vector<IntegratorInfo>& integrator_catalogue();
// Creates an integrator by name; an unknown name throws InputError listing the valid names.
std::unique_ptr<Integrator> make_integrator(const std::string& name);

}  // namespace kiln
