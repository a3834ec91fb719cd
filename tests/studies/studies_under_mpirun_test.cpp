// Studies under mpirun (src/studies/study_ranks.h): `mpirun -n 2 kiln order|sweep|wp` spreads the runs over
// two processes and writes the JSON one process writes, but for the timings; more ranks than runs
// work; a bad scene ends every rank with its error, said once. Each runs the kiln binary under
// Debian's OpenMPI, as a user would.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>

#include "tests/support.h"

using namespace kiln;
namespace fs = std::filesystem;

namespace {

// What the test suite runs as (root in CI) and where (a container of few cores): OpenMPI refuses
// root without being told, places no more ranks than cores without --oversubscribe, and its
// shared-memory transport's single-copy path (CMA) needs ptrace rights that containers withhold.
const std::string mpirun =
    "OMPI_MCA_btl_vader_single_copy_mechanism=none mpirun --allow-run-as-root --oversubscribe --bind-to none";

struct Command {
  int status = -1;
  std::string output;  // standard output and error
};

// `launcher kiln arguments`, its exit status and what it printed.
Command run_kiln(const std::string& launcher, const std::string& arguments, const fs::path& log) {
  const std::string cmd = launcher + " " + KILN_BINARY + " " + arguments + " > " + log.string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

nlohmann::json read_json(const fs::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

// A study's JSON less what depends on how it ran: the wall times (per integrator in order and wp;
// sweep has none) and the number of ranks. Everything else must match exactly.
nlohmann::json without_timings(nlohmann::json study) {
  study.erase("ranks");
  if (study.contains("integrators"))
    for (auto& entry : study["integrators"]) entry.erase("wall_seconds");
  for (const char* estimate : {"estimate", "estimate_at_start"})
    if (study.contains(estimate)) study[estimate].erase("estimate_seconds");
  return study;
}

// Runs `study arguments` in one process with two threads and under `mpirun -n ranks` with one
// thread a rank; both must succeed and write the same NAME.json, timings aside.
void same_json_under_mpirun(const std::string& study, const std::string& arguments, int ranks) {
  const fs::path dir = testing::fresh_dir("mpirun_" + study);
  fs::create_directories(dir);
  const Command one = run_kiln("", study + " " + arguments + " --threads 2 --quiet --out " + (dir / "one").string(),
                           dir / "one.log");
  const Command many = run_kiln(mpirun + " -n " + std::to_string(ranks),
                            study + " " + arguments + " --threads 1 --quiet --out " + (dir / "many").string(),
                            dir / "many.log");
  INFO(one.output << many.output);
  REQUIRE(one.status == 0);
  REQUIRE(many.status == 0);
  CHECK(many.output.empty());  // --quiet: no rank prints
  const nlohmann::json a = read_json(dir / "one" / (study + ".json"));
  const nlohmann::json b = read_json(dir / "many" / (study + ".json"));
  // The processes really were `ranks` MPI ranks sharing one study, not copies of the whole study.
  CHECK(a["ranks"] == 1);
  CHECK(b["ranks"] == ranks);
  // Every run's results in their place: a dropped or misplaced run changes a value (and one that
  // two ranks report stops kiln with an internal error).
  const nlohmann::json differences = nlohmann::json::diff(without_timings(a), without_timings(b));
  INFO("differences: " << differences.dump());
  CHECK(differences.empty());
  // Every run ran (a run that did not has no wall time).
  if (b.contains("integrators"))
    for (const auto& entry : b["integrators"])
      for (const auto& seconds : entry["wall_seconds"]) CHECK(seconds.get<double>() > 0);
  fs::remove_all(dir);
}

}  // namespace

TEST_CASE("kiln order, sweep and wp under mpirun -n 2 write the JSON of one process, timings aside",
          "[study][mpi]") {
  // Two integrators at three levels (steps of unequal cost), a sweep whose bisection runs one probe
  // at a time (one rank idle), and a work-precision study with its fine reference run and repeats.
  same_json_under_mpirun("order", testing::case_path("harmonic_contact_pair.yaml") +
                                      " --integrators velocity-verlet,erk4 --dt 1e-4 --levels 3", 2);
  same_json_under_mpirun("sweep", testing::case_path("harmonic_contact_pair.yaml") +
                                      " --integrator velocity-verlet --dt-min 1e-5 --dt-max 1e-3 --points 5 "
                                      "--t-end 0.02", 2);
  same_json_under_mpirun("wp", testing::case_path("t4_two_particle_conduction.yaml") +
                                   " --integrators velocity-verlet,erk4 --dts 4e-3,2e-3 --repeats 2 --reference fine "
                                   "--fine-rtol 1e-9", 2);
}

TEST_CASE("a study of two runs under mpirun -n 3 leaves a rank idle and writes the same JSON", "[study][mpi]") {
  same_json_under_mpirun("order", testing::case_path("harmonic_contact_pair.yaml") +
                                      " --integrators velocity-verlet --dt 1e-4 --levels 2", 3);
}

TEST_CASE("a bad study under mpirun ends every rank with exit code 2, the error said once, nothing written",
          "[study][mpi]") {
  const fs::path dir = testing::fresh_dir("mpirun_bad");
  fs::create_directories(dir);
  const Command bad = run_kiln(mpirun + " -n 2",
                           "order " + testing::case_path("harmonic_contact_pair.yaml") +
                               " --integrators velocity-verlet --dt 1e-4 --quantity positon --out " +
                               (dir / "out").string(),
                           dir / "log");
  INFO(bad.output);
  CHECK(bad.status == 2);
  const std::string error = "error: unknown quantity 'positon'";
  const size_t first = bad.output.find(error);
  REQUIRE(first != std::string::npos);
  CHECK(bad.output.find(error, first + 1) == std::string::npos);
  CHECK_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}
