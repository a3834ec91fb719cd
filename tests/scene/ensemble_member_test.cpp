// ensemble_member (src/scene/scene.h): member 0 is the scene as written, other members redraw
// everything the scene declares random (fills, lattice jitter, random radii, random velocities)
// and nothing else, the same way every time.
#include <catch2/catch.hpp>

#include <string>

#include "src/scene/scene_yaml.h"
#include "src/studies/study_ensemble.h"
#include "tests/support.h"

using namespace kiln;

namespace {

const std::string random_scene = R"(name: ensemble
materials:
  glass: {density: 2500, stiffness: 1.0e4, restitution: 0.5}
particles:
  - material: glass
    radius: 0.001
    fill: {rectangle: [0, 0, 0.05, 0.05], count: 30, seed: 7}
  - material: glass
    radius: {uniform: [0.001, 0.0015]}
    lattice: {origin: [0, 0.06], spacing: 0.004, rows: 2, columns: 5, jitter: 1.0e-4, seed: 3}
    random_velocity: {max: 0.1, seed: 5}
  - material: glass
    radius: 0.001
    at: [[0.1, 0.1]]
dt: 1.0e-6
t_end: 0.001
)";

}  // namespace

TEST_CASE("ensemble member 0 is the scene as written; another member redraws only what is random, reproducibly",
          "[scene]") {
  const Scene written = parse_scene(random_scene, "e.yaml");
  const Scene zero = parse_scene(random_scene, "e.yaml", {"ensemble_member=0"});
  const Scene one = parse_scene(random_scene, "e.yaml", {"ensemble_member=1"});
  const Scene one_again = parse_scene(random_scene, "e.yaml", {"ensemble_member=1"});
  const Scene two = parse_scene(random_scene, "e.yaml", {"ensemble_member=2"});
  REQUIRE(written.n_particles() == 41);
  REQUIRE(one.n_particles() == 41);
  for (int i = 0; i < written.n_particles(); ++i) {
    CHECK(zero.position[i].x == written.position[i].x);
    CHECK(one_again.position[i].x == one.position[i].x);
    CHECK(one_again.velocity[i].x == one.velocity[i].x);
  }
  // The fill (0..29), the jittered lattice with its random radii and velocities (30..39) differ;
  // the disc placed at a point (40) does not.
  int moved = 0, resized = 0, sped = 0;
  for (int i = 0; i < 40; ++i) {
    moved += one.position[i].x != written.position[i].x && two.position[i].x != one.position[i].x;
    if (i >= 30) {
      resized += one.radius[i] != written.radius[i];
      sped += one.velocity[i].x != written.velocity[i].x;
    }
  }
  CHECK(moved == 40);
  CHECK(resized == 10);
  CHECK(sped == 10);
  CHECK(one.position[40].x == written.position[40].x);
  CHECK(written.random_sources.size() == 2);
  CHECK(testing::error_of(random_scene, {"ensemble_member=-1"}).find("key 'ensemble_member'") != std::string::npos);
}

TEST_CASE("a scene with nothing random names no random source", "[scene]") {
  CHECK(parse_scene(testing::two_discs_on_a_floor, "t.yaml").random_sources.empty());
}

TEST_CASE("ensemble members whose scene cannot be built are skipped and named", "[scene]") {
  // T6's fill of 214 discs is near its jamming limit: member 3's draw places only 211.
  Members members(testing::case_path("t6_drum.yaml"), {});
  CHECK(members.number(0) == 0);
  CHECK(members.number(2) == 2);
  CHECK(members.number(3) == 4);
  REQUIRE(members.skipped().size() == 1);
  CHECK(members.skipped().front().first == 3);
  CHECK(members.skipped().front().second.find("placed only 211 of 214") != std::string::npos);
}
