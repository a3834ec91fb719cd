// The colour scale of a picture: robust to outliers, honest about a constant field, with a length
// scale of a round size.
#pragma once
#include <string>
#include <vector>

namespace kiln {

struct ColourScale {
  double low = 0, high = 1;   // the values drawn at the two ends of the colour bar
  bool constant = false;      // every value equal to round-off: one colour, one label
  bool clipped_low = false;   // some values lie below `low` (drawn in its colour)
  bool clipped_high = false;  // some lie above `high`
  // Position of v on the scale, clamped to [0, 1] (0.5 for a constant field).
  double position(double v) const;
};

// The 2nd to 98th percentile of the finite values, widened to the full range when that is at most
// twice as wide: one fast disc among a resting heap is clipped instead of turning the heap into
// the lowest colour, while an ordinary spread keeps its true ends. A field whose values agree to
// 1e-9 of their magnitude (round-off) is constant.
ColourScale colour_scale(const std::vector<double>& values);

// An end of the colour bar as text: digits enough to tell it from the other end (a hundredth of
// `span`, the bar's range, is resolved: 299.37 on a bar to 300, not 299), and 0 for a value that
// is zero to a millionth of the span (3.2e-11 C on a bar to 100 C).
std::string scale_label(double value, double span);

// The largest length of the form 1, 2 or 5 x 10^k not above `at_most` (m): a scale bar.
double round_length(double at_most);

}  // namespace kiln
