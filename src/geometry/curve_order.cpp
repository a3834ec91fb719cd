#include "src/geometry/curve_order.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>

namespace kiln {

uint32_t hilbert_index(uint32_t x, uint32_t y) {
  constexpr uint32_t side = 1u << hilbert_bits;
  uint32_t d = 0;
  for (uint32_t s = side / 2; s > 0; s /= 2) {
    const uint32_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
    d += s * s * ((3 * rx) ^ ry);
    // The sub-square's curve is the whole one turned: rotate (x, y) into its frame.
    if (ry == 0) {
      if (rx == 1) {
        x = side - 1 - x;
        y = side - 1 - y;
      }
      std::swap(x, y);
    }
  }
  return d;
}

void hilbert_order(const double* x, const double* y, int n, std::vector<int>& order, std::vector<uint64_t>& keys) {
  order.resize(n);
  if (n == 0) return;
  const auto [xlo, xhi] = std::minmax_element(x, x + n);
  const auto [ylo, yhi] = std::minmax_element(y, y + n);
  // One scale for both axes: the curve's cells stay square, so a rank step is a step in space
  // along either axis.
  const double span = std::max({*xhi - *xlo, *yhi - *ylo, 1e-300});
  const double cells = static_cast<double>((1u << hilbert_bits) - 1);
  auto cell = [&](double v, double lo) { return static_cast<uint32_t>(std::min(cells, (v - lo) / span * cells)); };
  keys.resize(n);
  for (int i = 0; i < n; ++i)
    keys[i] = (static_cast<uint64_t>(hilbert_index(cell(x[i], *xlo), cell(y[i], *ylo))) << 32) | static_cast<uint32_t>(i);
  std::sort(keys.begin(), keys.end());
  for (int r = 0; r < n; ++r) order[r] = static_cast<int>(keys[r] & 0xffffffffu);
}

double share_apart(const std::vector<CandidatePair>& pairs, int window) {
  if (pairs.empty()) return 0;
  long apart = 0;
  for (const CandidatePair& p : pairs) apart += std::abs(p.i - p.j) > window;
  return static_cast<double>(apart) / static_cast<double>(pairs.size());
}

}  // namespace kiln
