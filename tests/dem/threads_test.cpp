// Threads change nothing: a particle's contact sums are its rows added in the order of the list
// (on one thread as the contact loop makes them, on several from the rows each contact writes),
// and every sum goes over fixed blocks (src/base/parallel.h), so a run on 1, 2 or 4 threads ends in
// the same bits. The scene is large enough that every threaded loop (contacts, sums per particle,
// accelerations, the integrators' updates and work sums) runs in parallel: 9,000 rough, pressed
// discs in a periodic cell on a floor with friction and rolling resistance; hot, with dashpot and
// friction heat and conduction (the contact loop's general instantiation), and cold (its plain
// one, the benchmark's).
#include <omp.h>

#include <catch2/catch.hpp>
#include <cstring>
#include <sstream>

#include "integrators/integrator.h"
#include "src/dem/dem_system.h"
#include "src/base/parallel.h"
#include "src/scene/scene_yaml.h"
#include "tests/support.h"

namespace kiln {
namespace {

std::vector<double> final_state(const std::string& integrator, bool hot, int threads, int steps) {
  const Scene scene = parse_scene(testing::pressed_pile(hot), "pressed_pile");
  DemSystem system(scene);
  std::vector<double> y = system.initial_state();
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  auto stepper = make_integrator(integrator);
  stepper->start(system, 0, y.data(), scene.dt);
  for (int k = 0; k < steps; ++k) stepper->step();
  omp_set_num_threads(before);
  REQUIRE(system.particle_contacts().size() > 16 * sum_block);  // many blocks: the sums are split
  REQUIRE(system.particles() > 8192);
  return y;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

}  // namespace

TEST_CASE("a run ends in the same bits on 1, 2 and 4 threads", "[threads]") {
  for (const bool hot : {true, false})
    for (const char* integrator : {"velocity-verlet", "erk2"}) {
      INFO(integrator << (hot ? ", hot" : ", cold"));
      const std::vector<double> one = final_state(integrator, hot, 1, 60);
      CHECK(same_bits(one, final_state(integrator, hot, 2, 60)));
      CHECK(same_bits(one, final_state(integrator, hot, 4, 60)));
      // And the run did something: discs moved (and heat flowed and was made).
      const std::vector<double> start = DemSystem(parse_scene(testing::pressed_pile(hot), "p")).initial_state();
      CHECK_FALSE(same_bits(one, start));
    }
}

}  // namespace kiln
