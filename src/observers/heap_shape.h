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
// NaN figures where there is no heap to measure: fewer than three surface columns on a side, or
// discs spread over more than 2^20 columns of one mean diameter.
HeapShape measure_heap(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& r);

}  // namespace kiln
