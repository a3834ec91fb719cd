// Case quantities: what a standard case reports in summary.json beyond the energy ledger.
// A scene asks for them by name (`report: [bounce_heights]`); each samples the state after
// every step and writes its figures at the end.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "src/snapshot.h"

namespace kiln {

class DemSystem;

class Observer {
 public:
  virtual ~Observer() = default;
  virtual void sample(double /*t*/, const double* /*y*/) {}  // after every step; most need only the end
  virtual void report(double t, const double* y, nlohmann::json& summary) = 0;
  // Checkpoints: what sample() accumulated, under keys starting with `prefix`.
  virtual void save(Snapshot&, const std::string& /*prefix*/) const {}
  virtual void restore(const Snapshot&, const std::string& /*prefix*/) {}
};

const std::vector<std::string>& observer_names();
std::unique_ptr<Observer> make_observer(const std::string& name, const DemSystem& system);

// Heap figures from a settled pile (used by the `heap` observer, testable on its own).
struct HeapShape {
  double angle_left_deg = NAN, angle_right_deg = NAN, angle_deg = NAN;
  double packing_fraction = NAN;
};
HeapShape measure_heap(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& r);

}  // namespace kiln
