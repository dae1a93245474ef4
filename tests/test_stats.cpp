// Tests of stats.h against values computed by hand from the definitions, and Mann-Whitney results
// checked against scipy 1.10's scipy.stats.mannwhitneyu(x, y, alternative="two-sided").
#include <catch2/catch.hpp>
#include <cmath>
#include <functional>
#include <limits>
#include <vector>

#include "core/error.h"
#include "core/rng.h"
#include "report/stats.h"

using namespace roger;
using Catch::Matchers::Contains;

namespace {

std::vector<double> repeat(double v, int n) { return std::vector<double>(size_t(n), v); }

std::vector<double> concat(std::vector<double> a, const std::vector<double>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

const double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

TEST_CASE("mean and the two standard deviations on hand-computed samples", "[stats]") {
  const std::vector<double> xs{2, 4, 4, 4, 5, 5, 7, 9};
  CHECK(mean(xs) == Approx(5.0));
  CHECK(population_std(xs) == Approx(2.0));               // sqrt(32 / 8)
  CHECK(sample_std(xs) == Approx(std::sqrt(32.0 / 7.0)));  // 2.1381

  CHECK(population_std({3.0}) == 0.0);
  CHECK_THROWS_AS(sample_std({3.0}), Error);
  CHECK_THROWS_AS(mean({}), Error);
  CHECK_THROWS_WITH(mean({1.0, kNaN}), Contains("value 1") && Contains("finite"));
}

TEST_CASE("the paper's reward +- std is the population standard deviation", "[stats]") {
  // Table I, DC1: 49 episodes at +100 and one at -100 -> 96.0 +- 28.0.
  const auto dc1 = concat(repeat(100, 49), repeat(-100, 1));
  CHECK(mean(dc1) == Approx(96.0));
  CHECK(population_std(dc1) == Approx(28.0));
  CHECK(sample_std(dc1) == Approx(28.0 * std::sqrt(50.0 / 49.0)));  // 28.28: not the paper's
  // Table III, circle: 47 successes, 3 failures -> 88.0 +- 47.497.
  const auto circle = concat(repeat(100, 47), repeat(-100, 3));
  CHECK(mean(circle) == Approx(88.0));
  CHECK(population_std(circle) == Approx(47.497).epsilon(1e-5));
  // Table III, pentagon: 45 and 5 -> 80.0 +- 60.0.
  CHECK(population_std(concat(repeat(100, 45), repeat(-100, 5))) == Approx(60.0));
  // All successes: 100.0 +- 0.0 exactly.
  CHECK(mean(repeat(100, 50)) == 100.0);
  CHECK(population_std(repeat(100, 50)) == 0.0);
}

TEST_CASE("median and type-7 quantiles", "[stats]") {
  CHECK(median({3, 1, 2}) == 2.0);
  CHECK(median({4, 1, 3, 2}) == 2.5);
  CHECK(median({7}) == 7.0);
  // numpy.quantile([1, 2, 3, 4, 10], [0.1, 0.25, 0.5, 0.9]) = [1.4, 2, 3, 7.6].
  const std::vector<double> a{10, 1, 4, 2, 3};
  CHECK(quantile(a, 0.1) == Approx(1.4));
  CHECK(quantile(a, 0.25) == Approx(2.0));
  CHECK(quantile(a, 0.5) == Approx(3.0));
  CHECK(quantile(a, 0.9) == Approx(7.6));
  // numpy.quantile([3.5, -1, 2, 8], [0, 0.3, 0.75, 1]) = [-1, 1.7, 4.625, 8].
  const std::vector<double> b{3.5, -1, 2, 8};
  CHECK(quantile(b, 0.0) == -1.0);
  CHECK(quantile(b, 0.3) == Approx(1.7));
  CHECK(quantile(b, 0.75) == Approx(4.625));
  CHECK(quantile(b, 1.0) == 8.0);
  CHECK_THROWS_WITH(quantile(b, 1.5), Contains("[0, 1]"));
  CHECK_THROWS_AS(quantile(b, kNaN), Error);
  CHECK_THROWS_AS(median({}), Error);
}

TEST_CASE("interquartile mean, with fractional boundary values", "[stats]") {
  // n = 8: the middle four values.
  CHECK(interquartile_mean({8, 1, 7, 2, 6, 3, 5, 4}) == Approx(4.5));
  CHECK(interquartile_mean({1, 2, 3, 4, 100, -50, 5, 6}) == Approx((2 + 3 + 4 + 5) / 4.0));
  // n = 5: values own fifths of [0, 1]; weights 0.15, 0.2, 0.15 on the 2nd, 3rd and 4th.
  CHECK(interquartile_mean({16, 1, 8, 2, 4}) == Approx((0.15 * 2 + 0.2 * 4 + 0.15 * 8) / 0.5));
  CHECK(interquartile_mean({1, 2, 4, 8, 16}) == Approx(4.6));
  // n = 6: (x2 + 2 x3 + 2 x4 + x5) / 6.
  CHECK(interquartile_mean({1, 2, 4, 8, 16, 32}) == Approx(7.0));
  // n = 3: weights 1/12, 1/3, 1/12.
  CHECK(interquartile_mean({9, 1, 2}) == Approx(3.0));
  // n = 2: the mean; n = 1: the value.
  CHECK(interquartile_mean({1, 3}) == Approx(2.0));
  CHECK(interquartile_mean({-7}) == Approx(-7.0));
  // An outlier beyond the quartiles does not move it.
  CHECK(interquartile_mean({1, 2, 3, 4, 5, 6, 7, 1e9}) == Approx(4.5));
  CHECK_THROWS_AS(interquartile_mean({}), Error);
}

TEST_CASE("Wilson score interval of a success rate", "[stats]") {
  // 8 of 10: statsmodels' proportion_confint(8, 10, method="wilson") gives (0.49016, 0.94332).
  const ConfidenceInterval a = wilson_interval(8, 10);
  CHECK(a.estimate == Approx(0.8));
  CHECK(a.low == Approx(0.4901625).margin(1e-6));
  CHECK(a.high == Approx(0.9433178).margin(1e-6));
  // At 0 and n successes the interval is not empty: z^2 / (n + z^2) = 3.8415 / 13.8415 from the edge.
  CHECK(wilson_interval(0, 10).low == 0.0);
  CHECK(wilson_interval(0, 10).high == Approx(0.2775328).margin(1e-6));
  CHECK(wilson_interval(10, 10).low == Approx(0.7224672).margin(1e-6));
  CHECK(wilson_interval(10, 10).high == Approx(1.0));
  // More draws, a narrower interval: 97.5% of 200 worlds against 97.5% of 10000.
  CHECK(wilson_interval(195, 200).low == Approx(0.9428217).margin(1e-6));
  CHECK(wilson_interval(9750, 10000).low == Approx(0.9717528).margin(1e-6));
  CHECK(wilson_interval(8, 10, 0.99).low < a.low);
  CHECK_THROWS_WITH(wilson_interval(11, 10), Contains("11 successes of 10"));
  CHECK_THROWS_WITH(wilson_interval(0, 0), Contains("positive number"));
}

namespace {

// `policies` policies, each in `layouts` layouts of its own (policy p's from p * layouts) or, with
// `shared`, all in the same ones; succeeds(p, l) says whether policy p succeeds in layout l.
std::vector<RateCell> rate_cells(int policies, int layouts, bool shared, const std::function<bool(int, int)>& succeeds) {
  std::vector<RateCell> cells;
  for (int p = 0; p < policies; ++p)
    for (int l = 0; l < layouts; ++l)
      cells.push_back({p, (shared ? 0 : p * layouts) + l, succeeds(p, l) ? 1.0 : 0.0, 1.0});
  return cells;
}

double width(const RateInterval& r) { return r.ci.high - r.ci.low; }

}  // namespace

// What each case catches: a bootstrap that treats episodes as independent when they share a
// policy (heterogeneous policies) or a layout (a hard layout for all), and one that claims
// certainty where it saw no variation (every episode a success).
TEST_CASE("a pooled success rate's interval resamples what the episodes were drawn from", "[stats]") {
  // One policy in 200 layouts of its own: the layouts are the draws, and the interval is about
  // Wilson's (the floor: never narrower).
  const RateInterval one = pooled_rate_interval(rate_cells(1, 200, false, [](int, int l) { return l % 20 != 0; }), 3);
  CHECK(one.by == Resampled::kLayouts);
  CHECK(one.policies == 1);
  CHECK(one.layouts == 200);
  CHECK(one.ci.estimate == Approx(0.95));
  const ConfidenceInterval w200 = wilson_interval(190, 200);
  CHECK(one.ci.low <= w200.low);
  CHECK(one.ci.high >= w200.high);
  CHECK(width(one) < (w200.high - w200.low) * 1.15);

  // 50 policies alike (49 of 50 each) in layouts of their own: resampling policies varies nothing,
  // and the interval is Wilson's over the 2500 layouts exactly.
  const RateInterval alike = pooled_rate_interval(rate_cells(50, 50, false, [](int, int l) { return l != 7; }), 3);
  CHECK(alike.by == Resampled::kPolicies);
  CHECK(alike.layouts == 2500);
  CHECK(alike.ci.low == Approx(wilson_interval(2450, 2500).low));
  CHECK(alike.ci.high == Approx(wilson_interval(2450, 2500).high));

  // Half the policies succeed everywhere, half in 80% of their layouts: pooled 90%. Episodes as
  // independent draws would give Wilson's width over 2500 (2.3 points); the policies' spread (10
  // points, so a standard error of 1.4 points over 50 of them) makes it about 5.5.
  const RateInterval mixed =
      pooled_rate_interval(rate_cells(50, 50, false, [](int p, int l) { return p % 2 == 0 || l % 5 != 0; }), 3);
  CHECK(mixed.by == Resampled::kPolicies);
  CHECK(mixed.ci.estimate == Approx(0.9));
  CHECK(width(mixed) > 0.045);
  CHECK(width(mixed) < 0.065);
  CHECK(mixed.ci.low < 0.9);
  CHECK(mixed.ci.high > 0.9);

  // 20 policies alike in the same 50 layouts, 5 of which every policy fails: the layouts are the
  // draws, not the 1000 episodes. Resampling the layouts gives about 2 * 1.96 * sqrt(0.09 / 50) =
  // 16.6 points; Wilson over the 1000 episodes would claim 3.7.
  const RateInterval crossed = pooled_rate_interval(rate_cells(20, 50, true, [](int, int l) { return l % 10 != 3; }), 3);
  CHECK(crossed.by == Resampled::kPoliciesAndLayouts);
  CHECK(crossed.layouts == 50);
  CHECK(crossed.ci.estimate == Approx(0.9));
  CHECK(width(crossed) > 0.14);
  CHECK(width(crossed) < 0.20);

  // Every episode a success: open below, as Wilson's over the layouts is.
  const RateInterval all = pooled_rate_interval(rate_cells(20, 50, false, [](int, int) { return true; }), 3);
  CHECK(all.ci.high == 1.0);
  CHECK(all.ci.low == Approx(wilson_interval(1000, 1000).low));
  CHECK(all.ci.low < 0.997);

  // The same cells and seed, the same interval.
  const RateInterval again =
      pooled_rate_interval(rate_cells(50, 50, false, [](int p, int l) { return p % 2 == 0 || l % 5 != 0; }), 3);
  CHECK(again.ci.low == mixed.ci.low);
  CHECK(again.ci.high == mixed.ci.high);

  CHECK_THROWS_WITH(pooled_rate_interval({}, 1), Contains("at least one cell"));
  CHECK_THROWS_WITH(pooled_rate_interval({{0, 0, 2.0, 1.0}}, 1), Contains("cell 0 (policy 0, layout 0) has 2 successes of 1"));
  CHECK_THROWS_WITH(pooled_rate_interval({{0, 0, 0.0, 0.0}}, 1), Contains("has 0 successes of 0"));
}

TEST_CASE("bootstrap CI contains the true mean, is reproducible and honest", "[stats]") {
  Rng rng(7);
  std::vector<double> sample;
  for (int i = 0; i < 200; ++i) sample.push_back(rng.normal(5.0, 2.0));

  const ConfidenceInterval ci = bootstrap_ci(sample, mean, 42);
  CHECK(ci.level == 0.95);
  CHECK(ci.estimate == Approx(mean(sample)));
  CHECK(ci.low < 5.0);
  CHECK(ci.high > 5.0);
  CHECK(ci.low < ci.estimate);
  CHECK(ci.estimate < ci.high);
  // The width is about 2 * 1.96 * sigma / sqrt(n) = 0.554.
  CHECK(ci.high - ci.low == Approx(2 * 1.96 * 2.0 / std::sqrt(200.0)).epsilon(0.15));

  const ConfidenceInterval again = bootstrap_ci(sample, mean, 42);
  CHECK(again.low == ci.low);
  CHECK(again.high == ci.high);
  const ConfidenceInterval other = bootstrap_ci(sample, mean, 43);
  CHECK((other.low != ci.low || other.high != ci.high));

  // Any statistic: the median and the IQM, a 90% interval narrower than the 95% one.
  const ConfidenceInterval med = bootstrap_ci(sample, median, 1, 2000);
  CHECK(med.low < med.estimate);
  CHECK(med.high > med.estimate);
  const ConfidenceInterval iqm90 = bootstrap_ci(sample, interquartile_mean, 1, 4000, 0.90);
  const ConfidenceInterval iqm95 = bootstrap_ci(sample, interquartile_mean, 1, 4000, 0.95);
  CHECK(iqm90.high - iqm90.low < iqm95.high - iqm95.low);

  // A constant sample has a degenerate interval.
  const ConfidenceInterval flat = bootstrap_ci(repeat(100, 50), mean, 3, 500);
  CHECK(flat.low == 100.0);
  CHECK(flat.high == 100.0);

  CHECK_THROWS_AS(bootstrap_ci({}, mean, 1), Error);
  CHECK_THROWS_WITH(bootstrap_ci(sample, mean, 1, 0), Contains("resamples"));
  CHECK_THROWS_WITH(bootstrap_ci(sample, mean, 1, 100, 1.0), Contains("level"));
  CHECK_THROWS_AS(bootstrap_ci(sample, Statistic(), 1), Error);
}

TEST_CASE("bootstrap CI covers the true mean about 95% of the time", "[stats]") {
  Rng rng(2024);
  int covered = 0;
  const int kSamples = 200;
  for (int s = 0; s < kSamples; ++s) {
    std::vector<double> sample;
    for (int i = 0; i < 60; ++i) sample.push_back(rng.normal(-3.0, 1.5));
    const ConfidenceInterval ci = bootstrap_ci(sample, mean, uint64_t(s), 1000);
    covered += (ci.low <= -3.0 && -3.0 <= ci.high) ? 1 : 0;
  }
  // Percentile intervals under-cover slightly at n = 60; 95% +- sampling noise of 200 trials.
  CHECK(covered >= int(0.88 * kSamples));
  CHECK(covered <= int(0.99 * kSamples));
}

TEST_CASE("Mann-Whitney U: exact small-sample p-values without ties", "[stats]") {
  // Complete separation, 5 vs 5: U = 0, p = 2 / C(10, 5) = 2 / 252.
  const auto sep = mann_whitney_u({1, 2, 3, 4, 5}, {6, 7, 8, 9, 10});
  CHECK(sep.exact);
  CHECK(sep.u1 == 0.0);
  CHECK(sep.u2 == 25.0);
  CHECK(sep.p_value == Approx(2.0 / 252.0));
  // Swapping the samples swaps U, not p.
  const auto swapped = mann_whitney_u({6, 7, 8, 9, 10}, {1, 2, 3, 4, 5});
  CHECK(swapped.u1 == 25.0);
  CHECK(swapped.p_value == Approx(2.0 / 252.0));
  // scipy: U = 17, p = 0.1111111111111111 (exact).
  const auto classic = mann_whitney_u({19, 22, 16, 29, 24}, {20, 11, 17, 12});
  CHECK(classic.exact);
  CHECK(classic.u1 == 17.0);
  CHECK(classic.p_value == Approx(0.1111111111111111).epsilon(1e-10));
  // scipy: U = 1, p = 0.11428571428571428 (exact); the asymptotic one is 0.11161176829829224.
  const std::vector<double> a{1.5, 3.2, 0.7}, b{2.1, 4.4, 5.0, 3.9};
  CHECK(mann_whitney_u(a, b).u1 == 1.0);
  CHECK(mann_whitney_u(a, b).p_value == Approx(0.11428571428571428).epsilon(1e-10));
  const auto asym = mann_whitney_u(a, b, MannWhitneyMethod::kAsymptotic);
  CHECK_FALSE(asym.exact);
  CHECK(asym.p_value == Approx(0.11161176829829224).epsilon(1e-10));
  // 20 vs 20 (the largest automatic exact case), scipy: U = 87, p = 0.001766783843487427.
  const std::vector<double> x{2.041,  -2.556, 0.418, -0.568, -0.453, -0.216, -2.02,
                              -0.232, -0.865, 3.323, 0.226,  -0.353, -0.281, -0.668,
                              -1.055, -0.391, 0.482, -0.239, 0.958,  -0.2};
  const std::vector<double> y{0.824, 2.346, 1.345, 0.295, 0.617, 1.341,  2.735,
                              0.53,  0.556, 1.802, -0.086, 0.508, 1.683, 1.38,
                              0.892, 1.47,  -2.028, 1.821, -0.16, -0.869};
  const auto big = mann_whitney_u(x, y);
  CHECK(big.exact);
  CHECK(big.u1 == 87.0);
  CHECK(big.p_value == Approx(0.001766783843487427).epsilon(1e-9));
  CHECK(mann_whitney_u(x, y, MannWhitneyMethod::kAsymptotic).p_value ==
        Approx(0.0023412726074935374).epsilon(1e-9));
  // The exact distribution is limited to n1 * n2 <= 10000.
  std::vector<double> many_x, many_y;
  for (int i = 0; i < 101; ++i) many_x.push_back(2 * i);
  for (int i = 0; i < 100; ++i) many_y.push_back(2 * i + 1);
  CHECK_THROWS_WITH(mann_whitney_u(many_x, many_y, MannWhitneyMethod::kExact), Contains("10000"));
  many_x.pop_back();
  CHECK(mann_whitney_u(many_x, many_y, MannWhitneyMethod::kExact).p_value ==
        Approx(mann_whitney_u(many_x, many_y, MannWhitneyMethod::kAsymptotic).p_value)
            .epsilon(0.02));
  // One value each: U = 0 or 1, p = 1.
  CHECK(mann_whitney_u({1.0}, {2.0}).p_value == Approx(1.0));
}

// The two-sided permutation p-value of the rank sum over midranks, by listing every split (the
// test's reference for the exact method with ties).
static double permutation_p(const std::vector<double>& x, const std::vector<double>& y) {
  std::vector<double> all = x;
  all.insert(all.end(), y.begin(), y.end());
  std::vector<double> midrank(all.size());
  for (size_t i = 0; i < all.size(); ++i) {
    double below = 0, equal = 0;
    for (double v : all) below += v < all[i], equal += v == all[i];
    midrank[i] = below + (equal + 1) / 2;
  }
  double centre = 0, observed = 0;
  for (size_t i = 0; i < all.size(); ++i) centre += midrank[i] * double(x.size()) / double(all.size());
  for (size_t i = 0; i < x.size(); ++i) observed += midrank[i];
  size_t extreme = 0, splits = 0;
  for (unsigned mask = 0; mask < (1u << all.size()); ++mask) {
    if (size_t(__builtin_popcount(mask)) != x.size()) continue;
    double sum = 0;
    for (size_t i = 0; i < all.size(); ++i)
      if (mask & (1u << i)) sum += midrank[i];
    ++splits;
    extreme += std::abs(sum - centre) >= std::abs(observed - centre) - 1e-9;
  }
  return double(extreme) / double(splits);
}

TEST_CASE("Mann-Whitney U: ties give the exact permutation p for small samples, else the corrected normal",
          "[stats]") {
  // Midranks: 1 -> 1, the three 2s -> 3, the three 3s -> 6, 4 -> 8; R1 = 21, U1 = 21 - 15 = 6.
  const auto r = mann_whitney_u({1, 2, 2, 3, 4}, {2, 3, 3, 5, 6, 7});
  CHECK(r.exact);
  CHECK(r.u1 == 6.0);
  CHECK(r.u2 == 24.0);
  CHECK(r.p_value == Approx(permutation_p({1, 2, 2, 3, 4}, {2, 3, 3, 5, 6, 7})).epsilon(1e-12));
  CHECK(mann_whitney_u({1, 2, 2, 3, 4}, {2, 3, 3, 5, 6, 7}, MannWhitneyMethod::kExact).p_value == r.p_value);
  // A probe's case: times on a checkpoint grid, 2 against 2, separated but for a tie. The normal
  // approximation gave 0.245, below the least p an exact test of 2 against 2 can give (1/3).
  const auto grid = mann_whitney_u({100, 150}, {150, 200});
  CHECK(grid.exact);
  CHECK(grid.p_value == Approx(permutation_p({100, 150}, {150, 200})).epsilon(1e-12));
  CHECK(grid.p_value >= 1.0 / 3.0);
  const auto wide = mann_whitney_u({1, 1, 2, 5, 5, 5, 9}, {2, 3, 5, 8, 9, 9, 9, 12});
  CHECK(wide.p_value == Approx(permutation_p({1, 1, 2, 5, 5, 5, 9}, {2, 3, 5, 8, 9, 9, 9, 12})).epsilon(1e-12));
  // Ties with more than 8 a side: the normal approximation, as for scipy.
  std::vector<double> nine_x{1, 1, 2, 3, 4, 5, 6, 7, 8}, nine_y{8, 9, 10, 11, 12, 13, 14, 15, 16};
  CHECK_FALSE(mann_whitney_u(nine_x, nine_y).exact);
  CHECK(mann_whitney_u(nine_x, nine_y, MannWhitneyMethod::kExact).exact);
  // sigma^2 = 30/12 (12 - 48/110); z = (6 - 15 + 0.5) / sigma. scipy: p = 0.11390314458853068.
  const auto normal = mann_whitney_u({1, 2, 2, 3, 4}, {2, 3, 3, 5, 6, 7}, MannWhitneyMethod::kAsymptotic);
  CHECK_FALSE(normal.exact);
  const double sigma = std::sqrt(30.0 / 12.0 * (12.0 - 48.0 / 110.0));
  CHECK(normal.z == Approx((6.0 - 15.0 + 0.5) / sigma));
  CHECK(normal.p_value == Approx(0.11390314458853068).epsilon(1e-10));

  // 25 vs 25 with ties inside one sample, scipy asymptotic: U = 197, p = 0.025631063407437153.
  std::vector<double> x, y;
  for (int i = 0; i < 25; ++i) x.push_back(1 + 2 * i);
  for (int i = 0; i < 25; ++i) y.push_back(10 + 2 * i + 0.5 + i % 3);
  const auto large = mann_whitney_u(x, y);
  CHECK_FALSE(large.exact);
  CHECK(large.u1 == 197.0);
  CHECK(large.p_value == Approx(0.025631063407437153).epsilon(1e-10));

  // Everything tied: no evidence of a difference.
  const auto flat = mann_whitney_u(repeat(100, 50), repeat(100, 50));
  CHECK(flat.u1 == 1250.0);
  CHECK(flat.p_value == 1.0);
  // The paper's reward columns: 49 + 1 against 50 successes are not significantly different.
  const auto rewards = mann_whitney_u(concat(repeat(100, 49), repeat(-100, 1)), repeat(100, 50));
  CHECK(rewards.p_value > 0.3);

  CHECK_THROWS_AS(mann_whitney_u({}, {1.0}), Error);
  CHECK_THROWS_AS(mann_whitney_u({1.0, kNaN}, {1.0}), Error);
}

TEST_CASE("probability of improvement counts x below y, ties half", "[stats]") {
  CHECK(probability_of_improvement({1, 2, 3}, {4, 5, 6}) == 1.0);
  CHECK(probability_of_improvement({4, 5, 6}, {1, 2, 3}) == 0.0);
  CHECK(probability_of_improvement({1, 2}, {1, 2}) == Approx(0.5));
  // Pairs with x < y: 1 < {2, 3}, 2 < {3}: 3 of 4; plus the tie 2 = 2 at half: 3.5 / 4.
  CHECK(probability_of_improvement({1, 2}, {2, 3}) == Approx(0.875));
  // Equals u2 / (n1 n2) of the Mann-Whitney test.
  CHECK(probability_of_improvement({1, 2, 2, 3, 4}, {2, 3, 3, 5, 6, 7}) == Approx(24.0 / 30.0));
  CHECK_THROWS_AS(probability_of_improvement({}, {1}), Error);
}

TEST_CASE("censored times rank above every reached time and tie with each other", "[stats]") {
  const std::vector<CensoredTime> x{{100, true}, {200, true}, {300, true}, {1000, false}};
  const std::vector<CensoredTime> y{{150, true}, {500, false}, {800, false}};
  CHECK(fraction_reached(x) == Approx(0.75));
  CHECK(fraction_reached(y) == Approx(1.0 / 3.0));
  CHECK(censored_values(y) == std::vector<double>{150, 500, 800});
  // Ranks: 100 -> 1, 150 -> 2, 200 -> 3, 300 -> 4, the three censored -> 6; R1 = 14, U1 = 4.
  // Exact over the midranks' splits (ties among the censored); scipy's normal approximation on
  // [100, 200, 300, inf] vs [150, inf, inf]: U = 4, p = 0.5820796519295022.
  const auto r = mann_whitney_u_censored(x, y);
  CHECK(r.exact);
  CHECK(r.u1 == 4.0);
  CHECK(r.p_value == Approx(permutation_p({100, 200, 300, 1e9}, {150, 1e9, 1e9})).epsilon(1e-12));
  const auto normal = mann_whitney_u_censored(x, y, MannWhitneyMethod::kAsymptotic);
  CHECK_FALSE(normal.exact);
  CHECK(normal.p_value == Approx(0.5820796519295022).epsilon(1e-10));
  // x faster than y: 3 + 2 + 2 strict pairs and 2 censored ties at half, of 12.
  CHECK(probability_of_improvement_censored(x, y) == Approx(8.0 / 12.0));
  // A censored trial is slower than a reached one even when its budget is shorter.
  const std::vector<CensoredTime> short_budget{{50, false}}, slow{{900, true}};
  CHECK(probability_of_improvement_censored(short_budget, slow) == 0.0);
  CHECK(fraction_reached(short_budget) == 0.0);

  CHECK_THROWS_AS(fraction_reached({}), Error);
  CHECK_THROWS_WITH(mann_whitney_u_censored({{-1, true}}, y),
                    Contains("time 0"));
  CHECK_THROWS_AS(censored_values({{kNaN, false}}), Error);
}

// A summary over censored_values() is exact when it equals the same over censored_far_values():
// the true times lie between the two, and a censored trial inside a summary's window moves it.
TEST_CASE("a summary is exact when the censored trials lie outside its window", "[stats]") {
  std::vector<CensoredTime> times;
  for (int i = 0; i < 23; ++i) times.push_back({100.0 + 10.0 * i, true});
  times.push_back({1000, false});
  const std::vector<double> low = censored_values(times), far = censored_far_values(times);
  CHECK(far.back() > 1e100);
  CHECK(median(far) == median(low));  // the 12th and 13th of 24: reached ones
  CHECK(interquartile_mean(far) == interquartile_mean(low));  // ranks 7 to 18
  CHECK(mean(far) > mean(low));
  CHECK(quantile(far, 0.99) > quantile(low, 0.99));  // between the 23rd and the 24th
  // Seven of 24 censored: the IQM's window (ranks 7 to 18) takes the first of them, the median not.
  for (int i = 17; i < 23; ++i) times[size_t(i)] = {1000, false};
  const std::vector<double> low7 = censored_values(times), far7 = censored_far_values(times);
  CHECK(median(far7) == median(low7));
  CHECK(interquartile_mean(far7) > interquartile_mean(low7));
  // A censored trial whose budget is shorter than a reached time sorts among them: a bound.
  const std::vector<CensoredTime> short_budget{{100, true}, {50, false}, {300, true}};
  CHECK(median(censored_far_values(short_budget)) > median(censored_values(short_budget)));
  CHECK_THROWS_AS(censored_far_values({{kNaN, false}}), Error);
}

TEST_CASE("min:sec formatting like the paper's tables", "[stats]") {
  CHECK(format_min_sec(2994) == "49:54");   // Table I, B1
  CHECK(format_min_sec(1495) == "24:55");   // Table I, DC2
  CHECK(format_min_sec(90) == "1:30");      // Table II, DC6
  CHECK(format_min_sec(23989) == "399:49");  // Table II, B2: no hour field
  CHECK(format_min_sec(3600) == "60:00");
  CHECK(format_min_sec(0) == "0:00");
  CHECK(format_min_sec(5) == "0:05");
  // Rounded to the nearest second, halves up, carrying into the minutes.
  CHECK(format_min_sec(2494.6) == "41:35");
  CHECK(format_min_sec(59.4) == "0:59");
  CHECK(format_min_sec(59.5) == "1:00");
  CHECK(format_min_sec(3599.5) == "60:00");
  CHECK(format_min_sec(0.49) == "0:00");
  CHECK_THROWS_WITH(format_min_sec(-1), Contains("not a duration"));
  CHECK_THROWS_AS(format_min_sec(kNaN), Error);
  CHECK_THROWS_AS(format_min_sec(std::numeric_limits<double>::infinity()), Error);
}

TEST_CASE("percent improvement as in Tables I and II", "[stats]") {
  CHECK(percent_improvement(2994, 2495) == Approx(16.67).epsilon(1e-3));  // DC1 over B1
  CHECK(percent_improvement(2994, 1495) == Approx(50.07).epsilon(1e-3));  // DC2 over B1
  CHECK(percent_improvement(23989, 90) == Approx(99.62).epsilon(1e-4));   // DC6 over B2
  CHECK(percent_improvement(100, 150) == Approx(-50.0));
  CHECK_THROWS_AS(percent_improvement(0, 10), Error);
  CHECK_THROWS_AS(percent_improvement(10, kNaN), Error);
}
