// T6: the drum at 30 rpm lifts its bed up the rising (right) side, mixes the hot and the cold half
// and keeps the heat exactly (adiabatic drum).
#include <catch2/catch.hpp>

#include "src/scene_yaml.h"
#include "src/simulation.h"
#include "tests/support.h"

using namespace kiln;

TEST_CASE("T6 drum at 30 rpm: the bed rides up the rising side, the halves mix and heat is kept", "[drum][heavy]") {
  const Scene scene = load_scene(testing::case_path("t6_drum.yaml"));
  const nlohmann::json s = run_scene(scene, {"", true});
  const auto& h = s["mixing_history"];
  const auto lacey = h["lacey_index"].get<std::vector<double>>();
  const auto spread = h["temperature_std"].get<std::vector<double>>();
  INFO("Lacey index " << lacey.front() << " -> " << lacey.back() << ", temperature spread " << spread.front()
                      << " -> " << spread.back() << " K, tilt " << s["bed_tilt_deg"] << " deg");
  // Segregated at the start (halves side by side), well on the way to mixed after half a turn.
  CHECK(lacey.front() < 0.15);
  CHECK(lacey.back() > 0.3);
  // Conduction narrows the temperature spread (no walls exchange heat).
  CHECK(spread.front() == Approx(50).margin(0.5));
  CHECK(spread.back() < spread.front() - 3);
  const double heat = s["heat_content"].get<double>();
  CHECK(std::abs(s["energy"]["thermal_change"].get<double>()) < 1e-12 * heat);
  // Counter-clockwise rotation carries the bed to the right and tilts its surface up to the right.
  CHECK(s["bed_centre"][0].get<double>() > 0.02);
  CHECK(s["bed_tilt_deg"].get<double>() > 20);
}
