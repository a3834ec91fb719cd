// The picture's colour scale and length scale: what a reader of picture.png relies on.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "src/output/colour_scale.h"
#include "src/output/run_outputs.h"

// One fast disc among 300 at rest: the scale spans the resting discs' speeds, the fast one is
// clipped at the top (before, it took the whole bar and the heap was one colour).
TEST_CASE("one fast disc does not turn a resting heap one colour: it is clipped", "[picture]") {
  std::vector<double> speeds;
  for (int i = 0; i < 300; ++i) speeds.push_back(1e-4 * (i % 17));
  speeds.push_back(5.0);
  const kiln::ColourScale s = kiln::colour_scale(speeds);
  CHECK(s.high == Approx(1.6e-3));
  CHECK(s.low == 0);
  CHECK(s.clipped_high);
  CHECK_FALSE(s.clipped_low);
  CHECK(s.position(5.0) == 1);
  CHECK(s.position(8e-4) == Approx(0.5));
}

// An ordinary spread keeps its true ends: clipping is for outliers only.
TEST_CASE("a field spread evenly keeps its full range on the colour bar", "[picture]") {
  std::vector<double> temperatures;
  for (int i = 0; i <= 100; ++i) temperatures.push_back(20 + 0.8 * i);
  const kiln::ColourScale s = kiln::colour_scale(temperatures);
  CHECK(s.low == 20);
  CHECK(s.high == 100);
  CHECK_FALSE(s.clipped_low);
  CHECK_FALSE(s.clipped_high);
}

// A field equal to round-off (a frozen bed at 20 C after a tiny heat exchange) is one colour and
// one label, not a bar from 20 to 20.000000000001 in every colour.
TEST_CASE("a field constant to round-off is drawn as one colour with one label", "[picture]") {
  const kiln::ColourScale s = kiln::colour_scale({20.0, 20.0 + 1e-12, 20.0 - 3e-12, 20.0});
  CHECK(s.constant);
  CHECK(s.low == Approx(20.0));
  CHECK(s.position(20.0) == 0.5);
  CHECK(kiln::colour_scale({}).constant);
  CHECK(kiln::colour_scale({NAN, INFINITY}).constant);
  CHECK_FALSE(kiln::colour_scale({0.0, 1e-3}).constant);
}

TEST_CASE("the scale bar has a round length of at most the width given", "[picture]") {
  CHECK(kiln::round_length(0.037) == Approx(0.02));
  CHECK(kiln::round_length(0.06) == Approx(0.05));
  CHECK(kiln::round_length(0.0123) == Approx(0.01));
  CHECK(kiln::round_length(3e-5) == Approx(2e-5));
}

TEST_CASE("colour bar ends show the digits that tell them apart, and round-off zero as 0", "[picture]") {
  CHECK(kiln::scale_label(299.37, 300 - 299.37) == "299.37");
  CHECK(kiln::scale_label(300, 300 - 299.37) == "300");
  CHECK(kiln::scale_label(3.2e-11, 100) == "0");
  CHECK(kiln::scale_label(100, 100) == "100");
  CHECK(kiln::scale_label(0.0484, 1.73) == "0.0484");
  CHECK(kiln::scale_label(-2.5, 5) == "-2.5");
}

TEST_CASE("the picture's subtitle names the steps of each stage: settling, then heat alone", "[picture]") {
  const nlohmann::json settled_then_heated = {
      {"steps", 50360},
      {"integrator", "velocity-verlet"},
      {"frozen_at", 0.5},
      {"integrator_stats", {{"heat_stage", {{"steps", 360}, {"integrator", "imex1"}}}}}};
  CHECK(kiln::how_it_ended(settled_then_heated) ==
        "mechanics frozen at 0.5 s, heat to t_end; 50000 steps of velocity-verlet, then 360 of imex1 (heat alone)");
  const nlohmann::json plain = {{"steps", 100}, {"integrator", "erk4"}};
  CHECK(kiln::how_it_ended(plain) == "reached t_end; 100 steps of erk4");
}
