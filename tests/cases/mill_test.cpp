// C2: a tumbling mill with lifters (cases/c2_mill.yaml): impacts on the lifters, the drum's torque
// and power, the mixing of two species.
#include <catch2/catch.hpp>

#include <filesystem>
#include <numeric>

#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "tests/support.h"

using namespace kiln;

TEST_CASE("C2 mill: the lifters take impacts no harder than a ball falling across the mill, the histogram in "
          "result.h5 holds every impact, the drum draws power and the species mix",
          "[mill][heavy]") {
  const std::filesystem::path dir = testing::fresh_dir("mill");
  const Scene scene = load_scene(testing::case_path("c2_mill.yaml"), {"t_end=1"});
  const nlohmann::json s = run_scene(scene, {dir.string(), true});
  const double omega = 71 * 2 * M_PI / 60, radius = 0.1, g = 9.81;

  // Impacts per wall: mill.shell, mill.lifters (the drawing's groups, in order).
  const nlohmann::json& impacts = s["wall_impacts"];
  REQUIRE(impacts.size() == 2);
  REQUIRE(impacts[1]["name"] == "mill.lifters");
  const double lifter_impacts = impacts[1]["impacts"].get<double>();
  INFO("lifters: " << impacts[1] << "\nshell: " << impacts[0]);
  CHECK(lifter_impacts > 1000);
  // No blow is harder than a ball carried at the shell's speed to the top, falling across the
  // mill (2 R) and meeting a lifter coming the other way at the shell's speed.
  const double ball = 4.0 / 3 * M_PI * std::pow(0.004, 3) * 7800;
  const double fastest = std::sqrt(std::pow(omega * radius, 2) + 2 * g * 2 * radius) + omega * radius;
  CHECK(impacts[1]["largest_energy"].get<double>() < 0.5 * ball * fastest * fastest);
  CHECK(impacts[1]["mean_energy"].get<double>() > 0);
  // result.h5: one histogram row per wall, summing to that wall's impacts; edges a decade per ten bins.
  const std::vector<double> histogram = testing::read_dataset(dir / "result.h5", "impact_energy_histogram");
  const std::vector<double> edges = testing::read_dataset(dir / "result.h5", "impact_energy_bin_edges");
  REQUIRE(histogram.size() == 2 * (edges.size() - 1));
  const size_t bins = edges.size() - 1;
  CHECK(std::accumulate(histogram.begin() + bins, histogram.end(), 0.0) == lifter_impacts);
  CHECK(std::accumulate(histogram.begin(), histogram.begin() + bins, 0.0) == impacts[0]["impacts"].get<double>());
  CHECK(edges[10] == Approx(10 * edges[0]));

  // The drum drives the charge: each wall's power is its torque times the drum's speed, and the
  // mill draws power through its lifters above all.
  const nlohmann::json& walls = s["walls"];
  double power = 0;
  for (const auto& w : walls) {
    CHECK(w["mean_power"].get<double>() == Approx(-omega * w["mean_torque"].get<double>()).epsilon(1e-6));
    power += w["mean_power"].get<double>();
  }
  CHECK(power > 0);
  CHECK(walls[1]["mean_power"].get<double>() > walls[0]["mean_power"].get<double>());
  // Per frame as well: result.h5 wall_power (frames x walls).
  const std::vector<double> per_frame = testing::read_dataset(dir / "result.h5", "wall_power");
  CHECK(per_frame.size() == 2 * testing::read_dataset(dir / "result.h5", "time").size());

  // Balls start below the ore (segregated), and the lifters stir them in.
  const auto lacey = s["mixing_history"]["lacey_index"];
  INFO("Lacey index " << lacey.front() << " -> " << lacey.back());
  CHECK(lacey.front().get<double>() < 0.3);
  CHECK(lacey.back().get<double>() > lacey.front().get<double>() + 0.2);
  CHECK(std::abs(s["energy"]["balance_error"].get<double>()) < 1e-3 * s["energy"]["work_by_walls"].get<double>());
  std::filesystem::remove_all(dir);
}

TEST_CASE("species_mixing needs particles of two materials: a wall's material is not a species", "[mill]") {
  // Two materials, but the particles are all copper: the second is the floor's.
  const std::string one_species = testing::replaced(
      testing::replaced(testing::two_discs_on_a_floor, "  copper: {density: 8900, stiffness: 6000, restitution: 0.8}\n",
                        "  steel: {stiffness: 6000, restitution: 0.8}\n  copper: {density: 8900, stiffness: 6000, "
                        "restitution: 0.8}\n"),
      "{name: floor, material: copper", "{name: floor, material: steel") +
                                "report: [species_mixing]\n";
  const std::string message = testing::error_of(one_species);
  INFO(message);
  CHECK(message.find("'species_mixing' needs particles of two materials") != std::string::npos);
  CHECK(message.find("report") != std::string::npos);
}
