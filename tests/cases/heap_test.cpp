// T3: a poured heap comes to rest with a slope and a packing fraction in the physical range.
#include <catch2/catch.hpp>
#include <cmath>

#include "src/observers/heap_shape.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "tests/support.h"

using namespace kiln;

TEST_CASE("heap measurement recovers the slope and packing of a synthetic triangular pile", "[heap]") {
  // A hexagonal packing of equal discs (packing pi/(2 sqrt 3) = 0.9069) cut to a 30 degree triangle.
  std::vector<double> x, y, r;
  const double radius = 1e-3, dx = 2 * radius, dy = std::sqrt(3.0) * radius;
  const double half_width = 0.1, slope = std::tan(30 * M_PI / 180);
  for (int row = 0; row < 200; ++row)
    for (int col = -200; col <= 200; ++col) {
      const double px = col * dx + (row % 2 ? radius : 0), py = radius + row * dy;
      if (py + radius <= slope * (half_width - std::abs(px))) {
        x.push_back(px);
        y.push_back(py);
        r.push_back(radius);
      }
    }
  const HeapShape shape = measure_heap(x, y, r);
  CHECK(shape.angle_deg == Approx(30).margin(1.5));
  CHECK(shape.packing_fraction == Approx(M_PI / (2 * std::sqrt(3.0))).margin(0.01));
}

TEST_CASE("discs spread over kilometres make no heap: its figures are not numbers, and the run's summary is written",
          "[heap]") {
  // Issue 28's review: three 0.1 mm discs at x = -9e5, 0 and 9e5 m (within the scene's ranges)
  // crashed the finished run as it wrote its summary: the column count overflowed an int.
  const HeapShape far = measure_heap({-9e5, 0, 9e5}, {0, 0, 0}, {1e-4, 1e-4, 1e-4});
  CHECK(std::isnan(far.angle_deg));
  CHECK(std::isnan(far.packing_fraction));
  const auto dir = testing::fresh_dir("heap_far");
  const auto out = testing::run_kiln_command("run " + testing::case_path("../tests/fuzz/regressions/issue28_heap_report_far_discs.yaml") +
                                                 " --quiet --out " + dir.string(),
                                             dir.string() + ".log");
  CHECK(out.status == 0);
  CHECK(std::filesystem::exists(dir / "summary.json"));
}

TEST_CASE("T3: poured copper discs come to rest in a heap with a slope and random-close packing", "[heap][heavy]") {
  const Scene scene = load_scene(testing::case_path("t3_heap.yaml"), {"particles.0.fill.count=200"});
  const auto s = run_scene(scene, {"", true});
  // At rest: the run ended on its kinetic-energy threshold, well before t_end.
  CHECK(s["stopped_early"] == "at_rest");
  CHECK(s["energy"]["kinetic"].get<double>() < 1e-7);
  // A heap of frictional discs with rolling resistance stands at some degrees, not flat and
  // not steeper than friction allows (atan 0.5 = 26.6 degrees).
  CHECK(s["heap_angle_deg"].get<double>() > 3);
  CHECK(s["heap_angle_deg"].get<double>() < 26.6);
  // Random packing of polydisperse discs: between loose (0.72) and the hexagonal maximum (0.907).
  CHECK(s["packing_fraction"].get<double>() > 0.72);
  CHECK(s["packing_fraction"].get<double>() < 0.907);
  // The ledger closes to the first-order error of velocity Verlet with dashpots, against the
  // potential energy the pour released (the ledger's potential counts from the initial positions;
  // measured 3.6e-5 of it).
  CHECK(std::abs(s["energy"]["balance_error"].get<double>()) < 0.02 * -s["energy"]["potential"].get<double>());
}
