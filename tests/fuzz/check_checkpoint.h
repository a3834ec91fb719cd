// What the checkpoint fuzzer does with one input (tests/fuzz/checkpoint_fuzz.cpp), shared with the
// test that replays its corpus and findings (tests/run/checkpoint_edits_test.cpp): `kiln run
// --restart` on a changed checkpoint, its checksums written afresh, read back and resumed for a
// few steps. The checksums refuse a checkpoint changed after it was
// written (tests/base); this target is the adversary they cannot see, a checkpoint that is
// consistent but wrong (a tool, a bug or a hand wrote it): arrays cut short or grown, counts and
// indices out of range, values at the edges. Every input must end in an InputError (refused,
// naming what), an InstabilityError (a state the checks stop) or a run; anything else that
// escapes, a crash, a sanitizer report or a read past an array is a finding.
//
// The base is a checkpoint of a small drum (a turning wall, friction and rolling history, heat,
// contacts) written once per process. An input is an edit script of 16-byte records:
//   byte 0: the edit (mod 6): set a real element, set an integer element, resize a real array,
//           resize an integer array, overwrite text bytes, resize a text;
//   bytes 1-2: which array (mod the arrays of that kind); bytes 3-6: the element (mod its size);
//   bytes 7-14: the value (a double's or an int64's bits, text bytes, or a new size mod 2 n + 3).
// The scene's texts are left alone: a checkpoint of another scene is the scene fuzzer's input
// once read, and it would claim this machine's memory, not the fuzzer's.
#pragma once
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "src/base/error.h"
#include "src/base/snapshot.h"
#include "src/run/simulation.h"
#include "src/run/stability.h"
#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"

namespace kiln::fuzz {

namespace checkpoint_detail {

namespace fs = std::filesystem;

inline const fs::path& work_dir() {
  static const fs::path dir = fs::temp_directory_path() / ("kiln_checkpoint_fuzz_" + std::to_string(::getpid()));
  return dir;
}

// The base checkpoint, of the drum in `cases` (the repository's cases/), written once per process.
inline const Snapshot& base(const std::string& cases) {
  static const Snapshot s = [&] {
    const std::string file = cases + "/t6_drum.yaml";
    // At 0.15 s the thirty discs lie on the drum's wall and on each other: contact lists to edit.
    const std::vector<std::string> sets = {"particles.0.fill.count=30", "t_end=0.15", "output_interval=0.05"};
    RunOptions o;
    o.out_dir = (work_dir() / "base").string();
    o.quiet = true;
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    o.source = {file, text.str(), sets};
    run_scene(load_scene(file, sets), o);
    return Snapshot::read((work_dir() / "base" / "checkpoint.h5").string());
  }();
  return s;
}

template <class T>
T read_as(const uint8_t* bytes) {
  T v;
  std::memcpy(&v, bytes, sizeof v);
  return v;
}

// The keys an edit may touch: all but the scene's.
inline std::vector<std::string> editable(std::vector<std::string> keys) {
  std::erase_if(keys, [](const std::string& k) { return k.rfind("scene.", 0) == 0 || k == "kiln.checksums"; });
  return keys;
}

inline void edit(Snapshot& s, const uint8_t* r) {
  const int op = r[0] % 6;
  const unsigned which = read_as<uint16_t>(r + 1);
  const uint32_t at = read_as<uint32_t>(r + 3);
  const uint8_t* value = r + 7;
  if (op == 0 || op == 2) {
    const auto keys = editable(s.real_keys());
    if (keys.empty()) return;
    const std::string& key = keys[which % keys.size()];
    std::vector<double> v = s.reals(key);
    if (op == 0 && !v.empty()) v[at % v.size()] = read_as<double>(value);
    if (op == 2) v.resize(read_as<uint64_t>(value) % (2 * v.size() + 3), read_as<double>(value));
    s.put(key, v);
  } else if (op == 1 || op == 3) {
    const auto keys = editable(s.integer_keys());
    if (keys.empty()) return;
    const std::string& key = keys[which % keys.size()];
    std::vector<long long> v = s.integers(key);
    if (op == 1 && !v.empty()) v[at % v.size()] = read_as<int64_t>(value);
    if (op == 3) v.resize(read_as<uint64_t>(value) % (2 * v.size() + 3), read_as<int64_t>(value) % 64);
    s.put_integers(key, v);
  } else {
    const auto keys = editable(s.text_keys());
    if (keys.empty()) return;
    const std::string& key = keys[which % keys.size()];
    std::string v = s.text(key);
    if (op == 4)
      for (size_t k = 0; k < 8 && !v.empty(); ++k) v[(at + k) % v.size()] = static_cast<char>(value[k]);
    if (op == 5) v.resize(read_as<uint64_t>(value) % (2 * v.size() + 3), static_cast<char>(value[0]));
    s.put_text(key, v);
  }
}

}  // namespace checkpoint_detail

// One input: the edits applied to the base, the checkpoint written (checksums afresh), read back
// and resumed for four steps. A refusal or a stop is caught; anything else escapes.
inline void check_checkpoint(const uint8_t* data, size_t size, const std::string& cases) {
  using namespace checkpoint_detail;
  Snapshot s = base(cases);
  for (size_t k = 0; k + 16 <= size && k < 64 * 16; k += 16) edit(s, data + k);
  const std::string path = (work_dir() / "checkpoint.h5").string();
  s.write(path);
  try {
    const Snapshot checkpoint = Snapshot::read(path);
    RunOptions o;
    o.quiet = true;
    o.resume = &checkpoint;
    // Four steps past the checkpoint's time (the scene's dt, which the scene text fixes).
    const Scene scene = scene_of_checkpoint(checkpoint, {}, o.source);
    const double t = checkpoint.real("time");
    const Scene short_run =
        scene_of_checkpoint(checkpoint, {assignment("t_end", std::isfinite(t) ? t + 4 * scene.dt : scene.t_end)}, o.source);
    const StabilityEstimate estimate = estimate_stability(short_run);
    o.estimate = &estimate;
    run_scene(short_run, o);
  } catch (const InputError&) {
  } catch (const InstabilityError&) {
  }
}

}  // namespace kiln::fuzz
