// A checkpoint that is consistent but wrong (its checksums written afresh over changed arrays,
// counts, indices and values) is refused or resumed, never read past an array or crashed on: the
// checkpoint fuzzer's corpus and findings replayed, and edit scripts drawn at random
// (tests/fuzz/check_checkpoint.h). Under the sanitizer build a read past an array fails it.
#include <catch2/catch.hpp>

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

// In the `long` label: it finds an open kind. Once the per-contact lengths were right (a
// contact's two modes), some random scripts resume and never end in the step loop (a changed
// integrator state, not yet found; times a step cannot advance are refused already). The
// corpus replay above stays in the default suite.
TEST_CASE("checkpoints with random edits, their checksums afresh, are refused or resumed, never crashed on",
          "[checkpoint][hostile][long]") {
  std::mt19937_64 rng(28);
  for (int k = 0; k < 300; ++k) {
    std::vector<uint8_t> input(16 * (1 + rng() % 4));
    for (uint8_t& b : input) b = static_cast<uint8_t>(rng());
    CAPTURE(k);
    kiln::fuzz::check_checkpoint(input.data(), input.size(), cases_dir);
  }
}
