// A part's checkpoint is one list of its fields: the same visit saves and restores it.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "src/base/error.h"
#include "src/base/snapshot.h"

using namespace kiln;

namespace {

struct Part {
  double time = 0, step = 0;
  long steps = 0;
  bool built = false;
  std::vector<double> rates;
  std::vector<int> pairs;
  std::string note;
  void state(SnapshotFields& f) {
    f.reals("times", time, step);
    f.integers("counts", steps, built);
    f.field("rates", rates);
    f.field("pairs", pairs);
    f.field("note", note);
  }
};

}  // namespace

TEST_CASE("one list of fields saves a part and restores it exactly", "[snapshot]") {
  Part saved{0.1, 1e-300, 123456789012, true, {1.0 / 3, -0.0, 1.7e308}, {4, -5}, "drum"};
  Snapshot s;
  SnapshotFields out(s, "part.");
  saved.state(out);
  CHECK(s.reals("part.times") == std::vector<double>{0.1, 1e-300});
  CHECK(s.integers("part.counts") == std::vector<long long>{123456789012, 1});
  Part restored;
  SnapshotFields in(static_cast<const Snapshot&>(s), "part.");
  restored.state(in);
  CHECK(restored.time == saved.time);
  CHECK(restored.step == saved.step);
  CHECK(restored.steps == saved.steps);
  CHECK(restored.built);
  CHECK(restored.rates == saved.rates);
  CHECK(restored.pairs == saved.pairs);
  CHECK(restored.note == "drum");
}

TEST_CASE("a packed field of the wrong length is refused by its key, not read past its end", "[snapshot]") {
  Snapshot s;
  s.put("part.times", std::vector<double>{0.1});
  s.put_integers("part.counts", std::vector<long long>{1, 0});
  Part p;
  SnapshotFields in(static_cast<const Snapshot&>(s), "part.");
  CHECK_THROWS_WITH(p.state(in), Catch::Contains("holds 1 values in 'part.times' where 2 belong"));
  // A build whose state layout grew (a count added) reads an older build's checkpoint so: the
  // message says why and what to do.
  CHECK_THROWS_WITH(p.state(in), Catch::Contains("state layout differs") && Catch::Contains("rerun the scene from the start"));
}

TEST_CASE("a missing field is refused by its key", "[snapshot]") {
  Snapshot s;
  double v = 0;
  SnapshotFields in(static_cast<const Snapshot&>(s), "observer.0.");
  CHECK_THROWS_AS(in.field("last_gap", v), InputError);
  CHECK_THROWS_WITH(in.field("last_gap", v), Catch::Contains("'observer.0.last_gap'"));
}
