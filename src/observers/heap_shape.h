// Heap figures from a settled pile (case T3; the `heap` observer, src/observers/observe_heap.cpp),
// testable on their own.
#pragma once
#include <cmath>
#include <vector>

namespace kiln {

struct HeapShape {
  double angle_left_deg = NAN, angle_right_deg = NAN, angle_deg = NAN;
  double packing_fraction = NAN;
};
HeapShape measure_heap(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& r);

}  // namespace kiln
