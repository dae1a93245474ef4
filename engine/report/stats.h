// stats.h: honest statistics for reports over trials: location and spread, type-7 quantiles, the
// interquartile mean, bootstrap confidence intervals, the Mann-Whitney U test, the probability of
// improvement, right-censored times-to-threshold, and the paper's min:sec formatting.
//
// Every function throws roger::Error for input it cannot give a meaningful answer to (an empty
// sample, a NaN or infinite value, a probability outside [0, 1]); none returns NaN silently.
//
// Which standard deviation is which: population_std divides by n and is what the paper's tables
// report ("96.0 +- 28.0" for 49 episodes at +100 and one at -100); sample_std divides by n - 1 and
// is the unbiased-variance estimate a statistician would quote for a sample of trials.
//
// Censored times: a trial that never reached the success threshold has a time-to-threshold equal
// to its whole training budget, a right-censored value (CensoredTime{budget, false}). The rank
// statistics (mann_whitney_u_censored, probability_of_improvement_censored) rank every censored
// value above every reached value, whatever the budgets, and tie censored values with one another.
// Means and medians of censored_values() are lower bounds of the true ones; report
// fraction_reached() beside them.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace roger {

// The arithmetic mean of a non-empty sample.
double mean(const std::vector<double>& xs);

// Sample standard deviation (divides by n - 1); needs at least two values.
double sample_std(const std::vector<double>& xs);

// Population standard deviation (divides by n): the paper's "+- Std"; 0 for a single value.
double population_std(const std::vector<double>& xs);

// The median (the type-7 quantile at 0.5: the mean of the two middle values for even n).
double median(const std::vector<double>& xs);

// The q-quantile, 0 <= q <= 1, by linear interpolation between order statistics (Hyndman & Fan
// type 7, the default of R's quantile() and numpy.quantile).
double quantile(const std::vector<double>& xs, double q);

// The interquartile mean (Agarwal et al. 2021): the mean of the middle 50% of the sorted sample,
// each value owning 1/n of [0, 1] and weighted by how much of it lies in [0.25, 0.75], so the
// boundary values count fractionally when n is not a multiple of 4 (scipy's trim_mean(x, 0.25)
// instead drops floor(n/4) values at each end; the two agree when 4 divides n).
double interquartile_mean(const std::vector<double>& xs);

// A statistic of a sample, for bootstrap_ci (mean, median, interquartile_mean or any function).
using Statistic = std::function<double(const std::vector<double>&)>;

// A confidence interval around a point estimate.
struct ConfidenceInterval {
  double estimate = 0.0;  // the statistic of the sample itself
  double low = 0.0;       // lower bound
  double high = 0.0;      // upper bound
  double level = 0.95;    // coverage the interval was built for
};

// Percentile-bootstrap confidence interval of statistic: `resamples` resamples of xs with
// replacement drawn from roger::Rng(seed) (same inputs and seed, same interval on every machine),
// bounds at the type-7 quantiles (1 - level) / 2 and (1 + level) / 2 of the resampled statistics.
ConfidenceInterval bootstrap_ci(const std::vector<double>& xs, const Statistic& statistic,
                                uint64_t seed, int resamples = 10000, double level = 0.95);

// Wilson score interval of a success rate: `successes` of `n` independent Bernoulli draws (n > 0,
// 0 <= successes <= n; both may be fractional, an effective sample), at coverage `level`. Unlike
// the normal approximation it stays inside [0, 1] and is not empty at 0 or n successes
// (0 of 10: [0, 27.8%]).
ConfidenceInterval wilson_interval(double successes, double n, double level = 0.95);

// A pooled success rate's data, cell by cell: the episodes of one policy in one layout (a world
// seed: where Roger, the goal, the objects and the obstacles are). Policies and layouts are any
// integers that tell them apart.
struct RateCell {
  int64_t policy = 0;
  int64_t layout = 0;
  double successes = 0.0, episodes = 0.0;  // 0 <= successes <= episodes, episodes > 0
};

// Which draws a pooled rate's interval resampled (pooled_rate_interval).
enum class Resampled {
  kPolicies,            // several policies, no layout met by two of them: layouts nest in policies
  kLayouts,             // one policy: its layouts are the draws
  kPoliciesAndLayouts,  // policies sharing layouts: both, independently (crossed)
};

// The interval of a pooled success rate and how it was made.
struct RateInterval {
  ConfidenceInterval ci;  // estimate: the pooled rate, sum of successes over sum of episodes
  Resampled by = Resampled::kPolicies;
  int64_t policies = 0, layouts = 0;  // distinct ones among the cells
};

// The percentile bootstrap interval of sum(successes) / sum(episodes) over cells that respects how
// the episodes were drawn. Episodes of one policy are not independent draws (they share its
// learned choices), and neither are episodes of one layout (a hard layout is hard for every policy
// that meets it): a resample draws whole policies (Davison & Hinkley's cluster bootstrap) and,
// where some layout is met by two or more policies, whole layouts too, each with replacement and
// independently of the other (Owen's 2007 pigeonhole bootstrap for crossed random effects); a
// single policy's layouts are resampled alone. Each resample's rate weighs each cell by how many
// times its policy and its layout were drawn; `resamples` resamples from roger::Rng(seed), bounds at
// the type-7 quantiles (1 - level) / 2 and (1 + level) / 2. The interval is never narrower than
// Wilson's over the distinct layouts (the interval if every policy played alike): a resample of
// cells that all succeed, or all fail, varies nothing, and 100% of 50 policies is not a certainty.
// A resample whose drawn policies met none of its drawn layouts is drawn again (crossed designs
// with gaps). Throws roger::Error for no cells, or a cell with no episodes or impossible counts.
RateInterval pooled_rate_interval(const std::vector<RateCell>& cells, uint64_t seed, int resamples = 10000,
                                  double level = 0.95);

// Learning curves summarized at each point of a common grid, over trials: the mean and population
// std (Figures 3 and 4) and the interquartile mean with its percentile-bootstrap interval (the
// IQM figures and the dashboard). One entry per grid point.
struct CurveBands {
  std::vector<double> mean, std;              // mean and population std over trials
  std::vector<double> iqm, iqm_low, iqm_high;  // interquartile mean and its confidence interval
};

// The bands of curves given as values[trial][point] (every trial with the same number of points,
// at least one trial). Every point's interval is bootstrap_ci of interquartile_mean with seed
// `seed`, `resamples` resamples and coverage `level`: one set of resampled trials for the whole
// curve, so the band moves only where the curves do; the same curves give the same bands.
CurveBands curve_bands(const std::vector<std::vector<double>>& values, uint64_t seed, int resamples,
                       double level = 0.95);

// How mann_whitney_u computes its p-value.
enum class MannWhitneyMethod {
  kAuto,        // exact when both samples have at most 20 values, or at most 8 with ties
  kExact,       // the exact null distribution of U, over the midranks with ties (n1 * n2 <= 10000)
  kAsymptotic,  // normal approximation with tie correction and continuity correction
};

// The outcome of a two-sided Mann-Whitney U (Wilcoxon rank-sum) test.
struct MannWhitneyResult {
  double u1 = 0.0;       // U of the first sample: pairs with x > y, plus half the ties (scipy's U)
  double u2 = 0.0;       // U of the second sample, n1 * n2 - u1
  double p_value = 1.0;  // two-sided p-value, in [0, 1]
  double z = 0.0;        // continuity-corrected normal score of u1 (0 when exact)
  bool exact = false;    // whether p_value comes from the exact distribution
};

// Two-sided Mann-Whitney U test of whether x and y come from the same distribution. Matches
// scipy.stats.mannwhitneyu(x, y, alternative="two-sided", method="exact" or "asymptotic") without
// ties; with ties the exact p-value is the permutation test's over the midranks (scipy's exact
// method assumes none).
MannWhitneyResult mann_whitney_u(const std::vector<double>& x, const std::vector<double>& y,
                                 MannWhitneyMethod method = MannWhitneyMethod::kAuto);

// P(X < Y) + 0.5 P(X = Y) for X drawn from x and Y from y: for training times (lower is better)
// the probability that x's approach is faster than y's; for rewards (higher is better) swap the
// arguments. Equals u2 / (n1 n2) of mann_whitney_u(x, y).
double probability_of_improvement(const std::vector<double>& x, const std::vector<double>& y);

// A trial's time-to-threshold: reached, or right-censored at the trial's whole budget.
struct CensoredTime {
  double seconds = 0.0;  // time-to-threshold, or the budget when not reached
  bool reached = true;   // false: the threshold was never reached (right-censored)
};

// Fraction of trials, in [0, 1], that reached the threshold; needs at least one trial.
double fraction_reached(const std::vector<CensoredTime>& times);

// The times with each censored trial at its budget (summaries of these are lower bounds).
std::vector<double> censored_values(const std::vector<CensoredTime>& times);

// The times with each censored trial far above every time (1e200 s): the other end of what its
// true time can be. A summary that grows with each value (a mean, a median, an interquartile
// mean, a bootstrap interval's ends of one) lies between its value over censored_values() and
// its value over these, and one that gives a censored trial any weight is huge over these: so it
// is exact when the two are equal, and a lower bound otherwise (a median of 24 trials, one
// censored, is exact; their mean is not).
std::vector<double> censored_far_values(const std::vector<CensoredTime>& times);

// mann_whitney_u on times-to-threshold: censored trials rank above all reached ones, tied.
MannWhitneyResult mann_whitney_u_censored(
    const std::vector<CensoredTime>& x, const std::vector<CensoredTime>& y,
    MannWhitneyMethod method = MannWhitneyMethod::kAuto);

// probability_of_improvement on times (x faster than y), censored trials ranking as slowest.
double probability_of_improvement_censored(const std::vector<CensoredTime>& x,
                                           const std::vector<CensoredTime>& y);

// Simulated seconds as the paper's min:sec, rounded to the nearest second, minutes unbounded:
// 2994 -> "49:54", 90 -> "1:30", 23989 -> "399:49" (no hour field, as in Table II).
std::string format_min_sec(double seconds);

// The paper's "% Improvement" of a training time over the baseline's: 100 (baseline - value) /
// baseline (Table I: 49:54 -> 24:55 is 50.07%). The baseline must be positive.
double percent_improvement(double baseline, double value);

// The common time grid of a run's learning curves, in simulated seconds, and the curves on it.
struct CurveGrid {
  std::vector<double> t;                   // grid times (simulated seconds of training)
  std::vector<std::vector<double>> values; // per trial: its greedy reward at each grid time
};

// Puts each trial's checkpoints (simulated training seconds, greedy reward) on a common grid of
// `points` times from the latest first checkpoint to the latest last checkpoint (log-spaced when
// log_x), by linear interpolation between checkpoints; a trial that stopped early holds its last
// value. Trials without checkpoints are skipped.
CurveGrid curve_grid(const std::vector<std::vector<std::pair<double, double>>>& trials, int points, bool log_x);

}  // namespace roger
