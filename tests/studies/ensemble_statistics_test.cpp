// Ensemble statistics (src/studies/ensemble_statistics.h) on synthetic quantities whose bias and
// noise are known: the intervals cover the truth as often as their level says, the tests detect
// a bias of the size they promise with the power they promise, and the verdicts read as designed.
// Each rate is measured over 4,000 synthetic ensembles: its binomial standard deviation is at most
// 0.0079 (at a rate of 0.5), so the bounds below (4 standard deviations of the rate checked) fail
// a correct implementation about once in 15,000 runs, and are deterministic for a fixed seed.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "src/studies/ensemble_statistics.h"
#include "src/studies/study_ensemble.h"

using namespace kiln;

namespace {

constexpr int trials = 4000;
double binomial_sd(double p) { return std::sqrt(p * (1 - p) / trials); }

// One synthetic ensemble of n seeds: each seed's "fill" moves both runs by a shared amount
// (standard deviation `shared`), each run adds its own noise (`own`); the point is biased by `bias`.
struct Pair {
  std::vector<double> point, reference;
};
Pair synthetic(std::mt19937_64& rng, int n, double truth, double bias, double shared, double own) {
  std::normal_distribution<double> normal;
  Pair p;
  for (int k = 0; k < n; ++k) {
    const double fill = shared * normal(rng);
    p.reference.push_back(truth + fill + own * normal(rng));
    p.point.push_back(truth + bias + fill + own * normal(rng));
  }
  return p;
}

}  // namespace

TEST_CASE("a 95 % interval of an ensemble mean covers the true mean in 95 % of ensembles, at n = 4 and n = 16",
          "[ensemble]") {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> normal(2.5, 0.3);
  for (int n : {4, 16}) {
    int covered = 0;
    for (int t = 0; t < trials; ++t) {
      std::vector<double> v(n);
      for (double& x : v) x = normal(rng);
      const Ensemble e = ensemble_of(v, 0.95);
      covered += e.low <= 2.5 && 2.5 <= e.high;
    }
    INFO("n = " << n << ", coverage " << double(covered) / trials);
    CHECK(std::fabs(double(covered) / trials - 0.95) < 4 * binomial_sd(0.95));
  }
}

TEST_CASE("a 90 % interval covers in 90 %: the level is the one asked, not a fixed 95 %", "[ensemble]") {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> normal(0, 1);
  int covered = 0;
  for (int t = 0; t < trials; ++t) {
    std::vector<double> v(6);
    for (double& x : v) x = normal(rng);
    const Ensemble e = ensemble_of(v, 0.90);
    covered += e.low <= 0 && 0 <= e.high;
  }
  CHECK(std::fabs(double(covered) / trials - 0.90) < 4 * binomial_sd(0.90));
}

TEST_CASE("the paired, Welch and one-sample tests keep their false alarms at 5 % when there is no bias",
          "[ensemble]") {
  std::mt19937_64 rng(3);
  int paired = 0, welch = 0, exact = 0;
  for (int t = 0; t < trials; ++t) {
    const Pair p = synthetic(rng, 8, 30.0, 0.0, 1.0, 0.2);
    paired += paired_bias(p.point, p.reference, 0.95, 0.8).detected();
    welch += welch_bias(p.point, p.reference, 0.95, 0.8).detected();  // valid, if weak, on paired seeds too
    exact += exact_bias(p.point, 30.0, 0.95, 0.8).detected();
  }
  CHECK(std::fabs(double(paired) / trials - 0.05) < 4 * binomial_sd(0.05));
  CHECK(std::fabs(double(exact) / trials - 0.05) < 4 * binomial_sd(0.05));
  // Welch's test treats the shared fill as noise twice over: it alarms less than its level, never more.
  CHECK(double(welch) / trials < 0.05 + 4 * binomial_sd(0.05));
}

TEST_CASE("a bias of the size a test calls detectable is detected with the power it promises", "[ensemble]") {
  // The smallest detectable bias is (t_{0.975} + t_{0.8}) SE; with the true SE of the paired
  // differences (sqrt 2 x 0.2 / sqrt 8) the t test's power there is 0.80 to within the
  // approximation of the noncentral t by a shifted central t (about 0.01 at 7 degrees of freedom).
  std::mt19937_64 rng(4);
  const int n = 8;
  const double se = std::sqrt(2.0) * 0.2 / std::sqrt(n);
  const double bias = (t_quantile(n - 1, 0.975) + t_quantile(n - 1, 0.8)) * se;
  int detected = 0;
  for (int t = 0; t < trials; ++t) {
    const Pair p = synthetic(rng, n, 30.0, bias, 1.0, 0.2);
    detected += paired_bias(p.point, p.reference, 0.95, 0.8).detected();
  }
  INFO("power " << double(detected) / trials);
  CHECK(std::fabs(double(detected) / trials - 0.8) < 0.02 + 4 * binomial_sd(0.8));
}

TEST_CASE("pairing the seeds cancels the fill's noise: a bias 20 times below the spread of the runs is found",
          "[ensemble]") {
  std::mt19937_64 rng(5);
  const Pair p = synthetic(rng, 8, 30.0, 0.05, 1.0, 0.01);
  const Bias paired = paired_bias(p.point, p.reference, 0.95, 0.8);
  const Bias welch = welch_bias(p.point, p.reference, 0.95, 0.8);
  CHECK(paired.detected());
  CHECK(paired.low < 0.05);
  CHECK(paired.high > 0.05);
  CHECK_FALSE(welch.detected());
  CHECK(welch.detectable > 20 * paired.detectable);
  CHECK(paired.test == "paired t");
}

TEST_CASE("verdicts: within a tolerance, biased by X +- Y, or no bias detectable at this N", "[ensemble]") {
  Bias b;
  b.n = 8;
  b.estimate = 0.01;
  b.low = -0.02;
  b.high = 0.04;
  b.detectable = 0.05;
  CHECK(verdict_of(b, 0.05) == BiasVerdict::within_tolerance);
  CHECK(describe(b, 0.05).rfind("within 0.05", 0) == 0);
  CHECK(verdict_of(b, 0.03) == BiasVerdict::undetected);  // the interval reaches past 0.03: undecided
  CHECK(describe(b, 0.03).find("more seeds may decide") != std::string::npos);
  CHECK(describe(b, 0).find("no bias detectable at N = 8 (smallest detectable 0.05)") == 0);
  b.estimate = 0.3;
  b.low = 0.2;
  b.high = 0.4;
  CHECK(verdict_of(b, 0.05) == BiasVerdict::biased);
  CHECK(describe(b, 0.05) == "biased by 0.3 +- 0.1");
  b.low = NAN;
  CHECK(describe(b, 0.05).find("no verdict") == 0);
}

TEST_CASE("an ensemble of one has a mean and no interval; mismatched pairs are refused", "[ensemble]") {
  const Ensemble one = ensemble_of({1.5}, 0.95);
  CHECK(one.mean == 1.5);
  CHECK(std::isnan(one.se));
  CHECK(std::isnan(one.low));
  CHECK_THROWS(paired_bias({1, 2, 3}, {1, 2}, 0.95, 0.8));
  CHECK_THROWS(paired_bias({1, 2}, {1, 2}, 1.5, 0.8));
  CHECK(std::isnan(paired_bias({1}, {1}, 0.95, 0.8).low));
}

TEST_CASE("a member that did not measure the quantity is named as such, not as a failed run", "[ensemble]") {
  // A step whose runs all ended is stable even when a quantity was not measured (a heap not yet
  // formed): sweep called such steps failed, and order dropped the whole ladder.
  std::vector<StudyRun> members(3, StudyRun("velocity-verlet", 1e-5));
  members[0].value = {1.0};
  members[1].value = {NAN};
  members[2].value = {2.0};
  bool unstable = true;
  CHECK(member_failure(members, &unstable).empty());
  CHECK_FALSE(unstable);
  CHECK(member_unmeasured(members, "heap_angle_deg").rfind("heap_angle_deg not measured by member 1", 0) == 0);
  CHECK(member_values(members).empty());
  members[2].failure = "stopped: unstable";
  members[2].unstable = true;
  CHECK(member_problem(members, "q").rfind("member 2: stopped", 0) == 0);
  CHECK(member_failure(members, &unstable) == "member 2: stopped: unstable");
  CHECK(unstable);
}
