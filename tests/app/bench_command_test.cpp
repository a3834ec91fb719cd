// `kiln bench` as bench/run.sh calls it: a pile written, then timed, the machine-readable line
// complete. Nothing here depends on how fast anything runs.
#include <map>

#include "src/scene/particle_file.h"
#include "tests/support.h"

namespace {

namespace fs = std::filesystem;

using Command = kiln::testing::CommandOutcome;
Command run(const std::string& arguments, const fs::path& log) { return kiln::testing::run_kiln_command(arguments, log); }

// The fields of the line "kiln-bench: key=value ..." (empty when there is none).
std::map<std::string, std::string> bench_fields(const std::string& output) {
  std::map<std::string, std::string> fields;
  const size_t at = output.find("kiln-bench:");
  if (at == std::string::npos) return fields;
  std::istringstream line(output.substr(at + 11, output.find('\n', at) - at - 11));
  for (std::string word; line >> word;) {
    const size_t eq = word.find('=');
    if (eq != std::string::npos) fields[word.substr(0, eq)] = word.substr(eq + 1);
  }
  return fields;
}

}  // namespace

// The smallest pile (4 columns, 200 discs) settles in a few seconds; then it is timed for a few
// hundred steps under velocity Verlet, and under ARKODE with heat.
TEST_CASE("kiln bench writes a periodic pile and times it, reporting every field", "[bench]") {
  const fs::path dir = kiln::testing::fresh_dir("bench_command");
  fs::create_directories(dir);
  const fs::path pile = dir / "pile.data", log = dir / "log.txt";
  const Command written = run("bench --write-pile " + pile.string() + " --columns 4", log);
  INFO(written.output);
  REQUIRE(written.status == 0);
  const kiln::ParticleFile read = kiln::read_particle_file(pile.string(), kiln::ParticleFileFormat::lammps, {INT_MAX, 2500});
  REQUIRE(read.size() == 200);
  CHECK(read.xlo == 0);
  CHECK(read.xhi == Approx(0.01));
  for (const kiln::Vec2 p : read.position) {
    CHECK((p.x >= read.xlo && p.x < read.xhi));
    CHECK((p.y > 0 && p.y < read.yhi));
  }

  for (const std::string& variant : {std::string(""), std::string(" --thermal --integrator erk2"), std::string(" --flowing")}) {
    const Command timed = run("bench --pile " + pile.string() + " --steps 300 --warmup 20" + variant, log);
    INFO(variant << "\n" << timed.output);
    REQUIRE(timed.status == 0);
    auto fields = bench_fields(timed.output);
    for (const char* key : {"n", "steps", "warmup", "integrator", "model", "loop_s", "particle_steps_per_s",
                            "ns_per_particle_step", "rhs_evals", "s_per_rhs", "s_per_step", "peak_rss_mb",
                            "run_rss_mb", "contacts_per_disc", "wall_contacts_per_disc", "rebuilds", "rebuild_ns_per_disc"})
      CHECK(fields.count(key) == 1);
    CHECK(fields["n"] == "200");
    CHECK(fields["steps"] == "300");
    CHECK(std::stod(fields["loop_s"]) > 0);
    CHECK(std::stod(fields["peak_rss_mb"]) > 0);
    // The run's own peak (its stability estimate left out) is within the process's: starting the
    // high-water mark again for it must not hide the estimate's peak from the process's figure.
    CHECK(std::stod(fields["run_rss_mb"]) > 0);
    CHECK(std::stod(fields["run_rss_mb"]) <= std::stod(fields["peak_rss_mb"]));
    // A settled pile: every disc in contact (3 to 4 neighbours in a hexagonal packing).
    CHECK(std::stod(fields["contacts_per_disc"]) > 2.5);
    CHECK(std::stod(fields["wall_contacts_per_disc"]) > 0.01);  // the lowest row: up to 4 of 200
    CHECK(std::stod(fields["wall_contacts_per_disc"]) <= 0.02);
    if (variant.find("erk2") != std::string::npos) {
      CHECK(fields["model"] == "thermal");
      CHECK(std::stol(fields["rhs_evals"]) >= 2 * 300);  // every stage evaluates the forces
    } else {
      CHECK(fields["rhs_evals"] == "300");
    }
  }
  // A file that is not a pile: the error names it and its line.
  const fs::path not_a_pile = dir / "not_a_pile.data";
  std::ofstream(not_a_pile) << "a title\n\n200 atoms\n\nPair Coeffs\n";
  const Command bad = run("bench --pile " + not_a_pile.string(), log);
  CHECK(bad.status == 2);
  CHECK_THAT(bad.output, Catch::Matchers::Contains(not_a_pile.string() + ":5: the section 'Pair Coeffs' is not read by kiln"));
  fs::remove_all(dir);
}

TEST_CASE("bench/run.sh is valid bash", "[bench]") {
  const fs::path script = fs::path(KILN_CASES_DIR).parent_path() / "bench" / "run.sh";
  REQUIRE(fs::exists(script));
  CHECK(std::system(("bash -n " + script.string()).c_str()) == 0);
}
