// The heap of a poured pile at the end (case T3): its flanks' angles and its packing fraction
// under the summit (src/observers/heap_shape.h).
#include "src/observers/heap_shape.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "src/dem/dem_system.h"
#include "src/observers/observer.h"
#include "src/observers/statistics.h"

namespace kiln {

namespace {

class HeapObserver final : public Observer {
 public:
  explicit HeapObserver(const DemSystem& sys) : sys_(sys) {}
  void report(double, const double* y, nlohmann::json& out) override {
    const int n = sys_.particles();
    std::vector<double> x(y + sys_.x_at(), y + sys_.x_at() + n), h(y + sys_.y_at(), y + sys_.y_at() + n), r(n);
    for (int i = 0; i < n; ++i) r[i] = sys_.radius(i);
    const HeapShape shape = measure_heap(x, h, r);
    out["heap_angle_deg"] = number_or_null(shape.angle_deg);
    out["heap_angle_left_deg"] = number_or_null(shape.angle_left_deg);
    out["heap_angle_right_deg"] = number_or_null(shape.angle_right_deg);
    out["packing_fraction"] = number_or_null(shape.packing_fraction);
  }

 private:
  const DemSystem& sys_;
};

}  // namespace

HeapShape measure_heap(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& r) {
  HeapShape shape;
  const size_t n = x.size();
  double rmean = 0, xmin = INFINITY, xmax = -INFINITY, floor = INFINITY;
  for (size_t i = 0; i < n; ++i) {
    rmean += r[i] / n;
    xmin = std::min(xmin, x[i] - r[i]);
    xmax = std::max(xmax, x[i] + r[i]);
    floor = std::min(floor, y[i] - r[i]);
  }
  // Surface profile: the highest disc top in columns one mean diameter wide. Discs spread over
  // more columns than max_columns make no heap to measure (three discs of 0.1 mm at x = -9e5, 0
  // and 9e5 m: the count overflowed an int, the index went negative, and the finished run
  // crashed writing its summary, its restart too).
  constexpr double max_columns = 1 << 20;
  const double width = 2 * rmean;
  const double span = std::ceil((xmax - xmin) / width);
  if (!(span <= max_columns)) return shape;
  const int bins = std::max(1, static_cast<int>(span));
  std::vector<double> top(bins, floor);
  for (size_t i = 0; i < n; ++i) {
    const int b = std::min(bins - 1, static_cast<int>((x[i] - xmin) / width));
    top[b] = std::max(top[b], y[i] + r[i]);
  }
  const int peak = static_cast<int>(std::max_element(top.begin(), top.end()) - top.begin());
  const double height = top[peak] - floor;
  // Slopes: columns whose surface lies between 20 % and 80 % of the heap height on each side
  // (away from the rounded summit and the scattered foot).
  LineFit left_slope, right_slope;
  for (int b = 0; b < bins; ++b) {
    const double rel = (top[b] - floor) / height;
    if (rel < 0.2 || rel > 0.8) continue;
    (b < peak ? left_slope : right_slope).add(xmin + (b + 0.5) * width, top[b]);
  }
  // Fewer than three columns on a side give no slope.
  auto angle = [](const LineFit& f) { return f.n >= 3 ? std::atan(std::abs(f.slope())) * 180 / M_PI : NAN; };
  shape.angle_left_deg = angle(left_slope);
  shape.angle_right_deg = angle(right_slope);
  shape.angle_deg = 0.5 * (shape.angle_left_deg + shape.angle_right_deg);

  // Packing fraction: share of a regular grid of sample points covered by discs, in a window
  // centred under the summit, from two diameters above the floor up to half the height, and as
  // wide as the heap is at half its height, halved.
  int left = peak, right = peak;
  while (left > 0 && top[left - 1] - floor > 0.5 * height) --left;
  while (right < bins - 1 && top[right + 1] - floor > 0.5 * height) ++right;
  const double cx = xmin + (peak + 0.5) * width;
  const double half_w = 0.25 * (right - left + 1) * width;
  double rmax = 0;
  for (double ri : r) rmax = std::max(rmax, ri);
  const double y0 = floor + 4 * rmax, y1 = floor + 0.5 * height;
  if (y1 <= y0 || half_w <= 2 * rmax) return shape;
  std::map<std::pair<long, long>, std::vector<size_t>> cells;
  const double cell = 2 * rmax;
  for (size_t i = 0; i < n; ++i) cells[{std::lround(std::floor(x[i] / cell)), std::lround(std::floor(y[i] / cell))}].push_back(i);
  const int samples = 200;
  long covered = 0;
  for (int a = 0; a < samples; ++a)
    for (int b = 0; b < samples; ++b) {
      const double px = cx - half_w + 2 * half_w * (a + 0.5) / samples;
      const double py = y0 + (y1 - y0) * (b + 0.5) / samples;
      const long gx = std::lround(std::floor(px / cell)), gy = std::lround(std::floor(py / cell));
      bool inside = false;
      for (long dx = -1; dx <= 1 && !inside; ++dx)
        for (long dy = -1; dy <= 1 && !inside; ++dy) {
          const auto it = cells.find({gx + dx, gy + dy});
          if (it == cells.end()) continue;
          for (size_t i : it->second)
            if ((px - x[i]) * (px - x[i]) + (py - y[i]) * (py - y[i]) < r[i] * r[i]) inside = true;
        }
      covered += inside;
    }
  shape.packing_fraction = static_cast<double>(covered) / (samples * samples);
  return shape;
}

std::unique_ptr<Observer> make_heap_observer(const DemSystem& system) { return std::make_unique<HeapObserver>(system); }

}  // namespace kiln
