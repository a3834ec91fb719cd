// The fuzzers' mutations and checkpoint edits outside libFuzzer, for scripts/hostile_campaign.py
// (a campaign a maintainer re-runs with the release build; README of tests/fuzz/):
//   fuzz_driver mutate SEED ROUNDS < scene.yaml > mutated.yaml
//     ROUNDS structural mutations (yaml_mutator.h) with seeds SEED, SEED + 1, ...; a round whose
//     mutation is empty (the text is not YAML, or nothing to change) keeps the text as it was.
//   fuzz_driver checkpoint EDIT_SCRIPT
//     the checkpoint fuzzer's input (check_checkpoint.h): edits applied to a small drum's
//     checkpoint, written with fresh checksums, resumed four steps. Exit 0 when it ended in a
//     refusal, a check's stop or a run; anything else escapes (exit 6 from the handler below, or
//     a signal).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/fuzz/check_checkpoint.h"
#include "tests/fuzz/yaml_mutator.h"

int main(int argc, char** argv) {
  const std::string mode = argc > 1 ? argv[1] : "";
  try {
    if (mode == "mutate" && argc == 4) {
      std::string text((std::istreambuf_iterator<char>(std::cin)), std::istreambuf_iterator<char>());
      const unsigned seed = static_cast<unsigned>(std::strtoul(argv[2], nullptr, 10));
      const int rounds = std::atoi(argv[3]);
      for (int k = 0; k < rounds; ++k) {
        const std::string next = kiln::fuzz::mutate_yaml(text, seed + static_cast<unsigned>(k));
        if (!next.empty()) text = next;
      }
      std::cout << text;
      return 0;
    }
    if (mode == "checkpoint" && argc == 3) {
      std::ifstream in(argv[2], std::ios::binary);
      const std::vector<uint8_t> data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      kiln::fuzz::check_checkpoint(data.data(), data.size(), KILN_CASES_DIR);
      std::filesystem::remove_all(kiln::fuzz::checkpoint_detail::work_dir());
      return 0;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_driver: uncaught %s\n", e.what());
    return 6;
  }
  std::fprintf(stderr, "usage: fuzz_driver mutate SEED ROUNDS < in > out | fuzz_driver checkpoint EDIT_SCRIPT\n");
  return 2;
}
