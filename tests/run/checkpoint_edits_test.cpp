// A checkpoint that is consistent but wrong (its checksums written afresh over changed arrays,
// counts, indices and values) is refused or resumed, never read past an array or crashed on: the
// checkpoint fuzzer's corpus and findings replayed, and edit scripts drawn at random
// (tests/fuzz/check_checkpoint.h). Under the sanitizer build a read past an array fails it.
#include <catch2/catch.hpp>
#include <hdf5.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <vector>

#include "tests/fuzz/check_checkpoint.h"
#include "tests/support.h"

namespace {

const std::string cases_dir = std::filesystem::path(kiln::testing::case_path("t6_drum.yaml")).parent_path().string();

std::vector<uint8_t> bytes_of(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// `s` written as `file`, read back and resumed for a millisecond (what --restart does).
void resume_for_a_millisecond(const kiln::Snapshot& s, const std::string& file) {
  const std::string path = (kiln::fuzz::checkpoint_detail::work_dir() / file).string();
  s.write(path);
  const kiln::Snapshot checkpoint = kiln::Snapshot::read(path);
  kiln::RunOptions o;
  o.quiet = true;
  o.resume = &checkpoint;
  const double t = checkpoint.real("time");
  const kiln::Scene scene = kiln::scene_of_checkpoint(checkpoint, {kiln::assignment("t_end", t + 1e-3)}, o.source);
  const kiln::StabilityEstimate estimate = kiln::estimate_stability(scene);
  o.estimate = &estimate;
  kiln::run_scene(scene, o);
}

}  // namespace

TEST_CASE("every checkpoint edit of the fuzzer's corpus and findings is refused or resumed, never crashed on",
          "[checkpoint][hostile]") {
  const std::filesystem::path fuzz = std::filesystem::path(cases_dir).parent_path() / "tests" / "fuzz";
  int replayed = 0;
  for (const auto& dir : {fuzz / "corpus" / "checkpoint", fuzz / "regressions"})
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
      if (dir.filename() == "regressions" && entry.path().filename().string().rfind("checkpoint_", 0) != 0) continue;
      INFO(entry.path().string());
      const std::vector<uint8_t> input = bytes_of(entry.path());
      kiln::fuzz::check_checkpoint(input.data(), input.size(), cases_dir);
      ++replayed;
    }
  CHECK(replayed >= 9);
}

TEST_CASE("checkpoints with random edits, their checksums afresh, are refused or resumed, never crashed on",
          "[checkpoint][hostile]") {
  std::mt19937_64 rng(28);
  for (int k = 0; k < 300; ++k) {
    std::vector<uint8_t> input(16 * (1 + rng() % 4));
    for (uint8_t& b : input) b = static_cast<uint8_t>(rng());
    CAPTURE(k);
    kiln::fuzz::check_checkpoint(input.data(), input.size(), cases_dir);
  }
}

// The kind the random scripts found last: an integrator whose step count or grid disagrees with
// its time. Its first step jumped the run 7e11 s ahead, and the checkpoint schedule, which then
// added its interval until it passed the step, never ended (the step loop hung). Both are refused
// by name now, and the schedule is reached by one division.
TEST_CASE("a checkpoint whose integrator's step count disagrees with its time is refused naming it",
          "[checkpoint][hostile]") {
  namespace fs = std::filesystem;
  for (const std::string integrator : {"velocity-verlet", "erk2"}) {
    INFO(integrator);
    const fs::path dir = kiln::testing::fresh_dir("count_" + integrator);
    const std::string file = kiln::testing::case_path("t6_drum.yaml");
    const std::vector<std::string> sets = {"particles.0.fill.count=30", "t_end=0.01", "output_interval=0.005",
                                           "integrator=" + integrator};
    kiln::RunOptions first;
    first.out_dir = dir.string();
    first.quiet = true;
    first.source = {file, kiln::testing::case_text("t6_drum.yaml"), sets};
    kiln::run_scene(kiln::load_scene(file, sets), first);
    kiln::Snapshot s = kiln::Snapshot::read((dir / "checkpoint.h5").string());
    const std::string key = integrator == "erk2" ? "integrator.grid_steps" : "integrator.count";
    s.put_integers(key, std::vector<long long>{350237998441162117LL});
    s.write((dir / "checkpoint.h5").string());
    const kiln::Snapshot checkpoint = kiln::Snapshot::read((dir / "checkpoint.h5").string());
    kiln::RunOptions o;
    o.quiet = true;
    o.resume = &checkpoint;
    o.out_dir = dir.string();
    const kiln::Scene scene = kiln::scene_of_checkpoint(checkpoint, {"t_end=0.02"}, o.source);
    CHECK_THROWS_WITH(kiln::run_scene(scene, o), Catch::Contains(key) && Catch::Contains("time"));
    fs::remove_all(dir);
  }
}

// What the checkpoint fuzzer found once it ran under libFuzzer: a drum's mixing series of unequal
// lengths (its report read past the shorter: a heap overflow under ASan) and a count kept among
// reals set to NaN (converted to an integer: undefined). Each is refused by name now, as is every
// observer array whose length the observer knows.
TEST_CASE("a checkpoint whose observer series differ in length or whose counts are not whole numbers is refused",
          "[checkpoint][hostile]") {
  using namespace kiln::fuzz::checkpoint_detail;
  const std::vector<std::pair<std::string, std::vector<double>>> edits = {
      {"observer.1.tilt", {0.0}}, {"observer.1.index", {}}, {"contacts", {1.0, NAN}}, {"contacts", {1.0, 1e300}},
      {"contacts", {1.0, 2.5}}};
  for (const auto& [key, value] : edits) {
    INFO(key);
    kiln::Snapshot s = base(cases_dir);
    REQUIRE(s.reals(key).size() >= 2);
    s.put(key, value);
    CHECK_THROWS_WITH(resume_for_a_millisecond(s, "observer.h5"), Catch::Contains(key));
  }
}

// Issue 28's review: a frame count of 1e15 was resumed as "-1530494976 frames"; it names the
// dataset now, with or without an output directory.
TEST_CASE("a checkpoint whose frame count is negative or beyond an int is refused, naming it", "[checkpoint][hostile]") {
  using namespace kiln::fuzz::checkpoint_detail;
  for (const long long frames : {1000000000000000LL, -1LL}) {
    kiln::Snapshot s = base(cases_dir);
    s.put_integer("frames", frames);
    CHECK_THROWS_WITH(resume_for_a_millisecond(s, "frames.h5"),
                      Catch::Contains("'frames' where a whole number in [0, 2147483647] belongs"));
  }
}

// Issue 28's review: `--restart --t-end 1e300` was refused as "--set: key 'output_interval'", a key
// a resumed run cannot change (the checkpoint's interval is given as an override).
TEST_CASE("a resumed run whose --t-end makes more than a million frames is refused naming t_end", "[checkpoint][hostile]") {
  using namespace kiln::fuzz::checkpoint_detail;
  const kiln::Snapshot s = base(cases_dir);
  kiln::SceneRecord source;
  CHECK_THROWS_WITH(kiln::scene_of_checkpoint(s, {"t_end=1e300"}, source),
                    Catch::Contains("key 't_end'") && Catch::Contains("give at most") &&
                        !Catch::Contains("output_interval ("));
}

// Issue 28's review: a contact pairing a particle with itself was resumed and stopped by the
// overlap check, blaming dt.
TEST_CASE("a checkpoint contact that pairs a particle with itself is refused, naming the lists", "[checkpoint][hostile]") {
  using namespace kiln::fuzz::checkpoint_detail;
  kiln::Snapshot s = base(cases_dir);
  std::vector<long long> j = s.integers("system.pairs.j");
  REQUIRE(!j.empty());
  j[0] = s.integers("system.pairs.i").at(0);
  s.put_integers("system.pairs.j", j);
  CHECK_THROWS_WITH(resume_for_a_millisecond(s, "self.h5"), Catch::Contains("(pairs.i, pairs.j) pair particle") &&
                                                               Catch::Contains("with itself"));
}

// Issue 28's second review: values a checkpoint gives that disagree with its own time and scene
// (fresh checksums) were resumed into an off-grid frame, a wrong summary, or a disc at 1e300 m/s.
TEST_CASE("a checkpoint whose stage frame, resumptions, freeze time, counts or speeds disagree with it is refused",
          "[checkpoint][hostile]") {
  using namespace kiln::fuzz::checkpoint_detail;
  const auto edited = [&](const std::string& key, auto value) {
    kiln::Snapshot s = base(cases_dir);
    if constexpr (std::is_same_v<decltype(value), std::vector<double>>)
      s.put(key, value);
    else
      s.put_integers(key, value);
    return s;
  };
  const kiln::Snapshot& b = base(cases_dir);
  const double t = b.real("time");
  CHECK_THROWS_WITH(resume_for_a_millisecond(edited("stage.frame", std::vector<double>{1.0}), "frame.h5"),
                    Catch::Contains("'stage.frame'"));
  CHECK_THROWS_WITH(resume_for_a_millisecond(edited("resumed_at", std::vector<double>{0.01, NAN}), "resumed.h5"),
                    Catch::Contains("'resumed_at'"));
  CHECK_THROWS_WITH(resume_for_a_millisecond(edited("frozen_at", std::vector<double>{0.5 * t}), "frozen.h5"),
                    Catch::Contains("'frozen_at'"));
  CHECK_THROWS_WITH(resume_for_a_millisecond(edited("totals", std::vector<long long>{-5, 1}), "totals.h5"),
                    Catch::Contains("a negative count"));
  std::vector<double> state = b.reals("state");
  kiln::Snapshot fast = b;
  kiln::SceneRecord record;
  const kiln::Scene drum = kiln::scene_of_checkpoint(b, {}, record);
  state[3 * drum.n_particles()] = 1e300;  // particle 0's vx (x, y and angle come first)
  fast.put("state", state);
  CHECK_THROWS_WITH(resume_for_a_millisecond(fast, "fast.h5"), Catch::Contains("faster than light"));
}

// Issue 28's review: a coordinate times 1e10 with fresh checksums (the adversary checksums cannot
// see) resumed, and the heap observer crashed at the run's end. No scene places a particle beyond
// 1e6 m; nor does a checkpoint now.
TEST_CASE("a checkpoint that places a particle beyond 1e6 m from the origin is refused, naming the state",
          "[checkpoint][hostile]") {
  using namespace kiln::fuzz::checkpoint_detail;
  kiln::Snapshot s = base(cases_dir);
  std::vector<double> state = s.reals("state");
  state[0] *= 1e10;
  s.put("state", state);
  CHECK_THROWS_WITH(resume_for_a_millisecond(s, "far.h5"), Catch::Contains("'state'") && Catch::Contains("beyond 1e6 m"));
}

// Issue 28's review: what kiln never writes in a checkpoint was an output failure (exit 4: a group
// where a dataset belongs, a variable-length string) or ran out of memory (a chunked dataset that
// declares 2^40 values in 117 kB: bad_alloc, exit 6). Each is bad input now, named, before a read.
TEST_CASE("a checkpoint holding a group, another kind of dataset or more values than it stores is refused by name",
          "[checkpoint][hostile]") {
  using namespace kiln::fuzz::checkpoint_detail;
  auto edited = [&](const std::string& file, auto&& edit) {
    const std::string path = (work_dir() / file).string();
    base(cases_dir).write(path);
    const hid_t h5 = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    REQUIRE(h5 >= 0);
    edit(h5);
    H5Fclose(h5);
    return path;
  };
  const std::string group = edited("group.h5", [](hid_t h5) { H5Gclose(H5Gcreate2(h5, "real/aaa", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT)); });
  CHECK_THROWS_WITH(kiln::Snapshot::read(group), Catch::Contains("'real/aaa' is not a dataset"));
  const std::string sparse = edited("sparse.h5", [](hid_t h5) {
    const hsize_t extent = hsize_t{1} << 40, chunk = 1024;
    const hid_t space = H5Screate_simple(1, &extent, nullptr), plist = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(plist, 1, &chunk);
    H5Dclose(H5Dcreate2(h5, "real/aab", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, plist, H5P_DEFAULT));
    H5Pclose(plist);
    H5Sclose(space);
  });
  CHECK_THROWS_WITH(kiln::Snapshot::read(sparse), Catch::Contains("'real/aab' declares 1099511627776 values"));
}
