// stats.cpp: see stats.h.
#include "report/stats.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <sstream>

#include "core/error.h"
#include "core/rng.h"

namespace roger {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string number(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

// Throws unless xs has at least `minimum` values, all finite; `what` names the caller.
void check_sample(const std::vector<double>& xs, const char* what, size_t minimum = 1) {
  if (xs.size() < minimum)
    throw Error(std::string("stats: ") + what + " needs at least " + std::to_string(minimum) +
                (minimum == 1 ? " value" : " values") + ", got " + std::to_string(xs.size()));
  for (size_t i = 0; i < xs.size(); ++i)
    if (!std::isfinite(xs[i]))
      throw Error(std::string("stats: ") + what + ": value " + std::to_string(i) + " is " +
                  number(xs[i]) + ", expected a finite number");
}

std::vector<double> sorted(std::vector<double> xs) {
  std::sort(xs.begin(), xs.end());
  return xs;
}

// Type-7 quantile of an already sorted, non-empty sample.
double sorted_quantile(const std::vector<double>& s, double q) {
  const double h = double(s.size() - 1) * q;
  const size_t lo = size_t(std::floor(h));
  if (lo + 1 >= s.size()) return s.back();
  return s[lo] + (h - double(lo)) * (s[lo + 1] - s[lo]);
}

// Mean of an already checked sample, with a compensated sum so +-100 rewards stay exact.
double plain_mean(const std::vector<double>& xs) {
  double sum = 0.0, c = 0.0;
  for (double v : xs) {
    const double y = v - c;
    const double t = sum + y;
    c = (t - sum) - y;
    sum = t;
  }
  return sum / double(xs.size());
}

// Sum of squared deviations from the mean (two-pass).
double squared_deviations(const std::vector<double>& xs) {
  const double m = plain_mean(xs);
  double ss = 0.0;
  for (double v : xs) ss += (v - m) * (v - m);
  return ss;
}

// The pieces of a Mann-Whitney test computed from the pooled midranks. Values may be +infinity
// (censored trials): they compare equal to one another and above every finite value.
struct RankSums {
  double u1 = 0.0;
  double tie_term = 0.0;  // sum over tie groups of t^3 - t
  bool ties = false;
  std::vector<long> doubled;  // every pooled value's midrank times two (an integer)
  long r1_doubled = 0;        // the first sample's rank sum times two
};

RankSums rank_sums(const std::vector<double>& x, const std::vector<double>& y) {
  struct Item {
    double value;
    bool first;
  };
  std::vector<Item> pooled;
  pooled.reserve(x.size() + y.size());
  for (double v : x) pooled.push_back({v, true});
  for (double v : y) pooled.push_back({v, false});
  std::sort(pooled.begin(), pooled.end(),
            [](const Item& a, const Item& b) { return a.value < b.value; });
  RankSums out;
  double r1 = 0.0;
  for (size_t i = 0; i < pooled.size();) {
    size_t j = i;
    while (j < pooled.size() && pooled[j].value == pooled[i].value) ++j;
    const double t = double(j - i);
    const double midrank = (double(i + 1) + double(j)) / 2.0;  // ranks i+1 .. j
    for (size_t k = i; k < j; ++k) {
      out.doubled.push_back(long(i + 1 + j));
      if (pooled[k].first) r1 += midrank, out.r1_doubled += long(i + 1 + j);
    }
    if (j - i > 1) {
      out.ties = true;
      out.tie_term += t * t * t - t;
    }
    i = j;
  }
  const double n1 = double(x.size());
  out.u1 = r1 - n1 * (n1 + 1.0) / 2.0;
  return out;
}

// P(U <= u) under the null hypothesis for samples of sizes m and n without ties, by the
// recurrence over which sample holds the largest value, in probabilities (no overflow).
double exact_cdf(size_t m, size_t n, double u) {
  const size_t max_u = m * n;
  const long target = long(std::floor(u + 1e-9));
  if (target < 0) return 0.0;
  if (size_t(target) >= max_u) return 1.0;
  // p[a][b][k]: probability that U = k for sizes (a, b); rows over a are rolled.
  const size_t width = max_u + 1;
  std::vector<double> prev((n + 1) * width, 0.0), cur((n + 1) * width, 0.0);
  for (size_t b = 0; b <= n; ++b) prev[b * width] = 1.0;  // a = 0: U = 0 surely
  for (size_t a = 1; a <= m; ++a) {
    std::fill(cur.begin(), cur.end(), 0.0);
    cur[0] = 1.0;  // b = 0: U = 0 surely
    for (size_t b = 1; b <= n; ++b) {
      const double px = double(a) / double(a + b);  // the largest value is an x: beats all b y's
      const double py = 1.0 - px;
      double* row = &cur[b * width];
      const double* from_x = &prev[b * width];      // (a - 1, b)
      const double* from_y = &cur[(b - 1) * width];  // (a, b - 1)
      const size_t top = a * b;
      for (size_t k = 0; k <= top; ++k) {
        double p = py * from_y[k];
        if (k >= b) p += px * from_x[k - b];
        row[k] = p;
      }
    }
    std::swap(prev, cur);
  }
  const double* dist = &prev[n * width];
  double cdf = 0.0;
  for (long k = 0; k <= target; ++k) cdf += dist[k];
  return std::min(1.0, cdf);
}

// The two-sided p-value with ties, exactly: over every split of the pooled midranks into a first
// sample of m values and the rest (each equally likely under the null hypothesis), the share whose
// rank sum lies at least as far from its mean as the observed one. Rank sums are counted by
// dynamic programming over the doubled midranks, which are integers: N m (N + 1) N steps at most.
double exact_p_with_ties(const RankSums& rs, size_t m) {
  const size_t n_all = rs.doubled.size();
  long total = 0;
  for (long r : rs.doubled) total += r;
  // ways[k][s]: subsets of k of the ranks seen so far whose doubled sum is s (exact up to 2^53).
  std::vector<std::vector<double>> ways(m + 1, std::vector<double>(size_t(total) + 1, 0.0));
  ways[0][0] = 1.0;
  for (size_t i = 0; i < n_all; ++i)
    for (size_t k = std::min(i + 1, m); k >= 1; --k)
      for (long s = total; s >= rs.doubled[i]; --s) ways[k][size_t(s)] += ways[k - 1][size_t(s - rs.doubled[i])];
  const long centre = long(m) * long(n_all + 1);  // the mean doubled rank sum of m values
  const long observed = std::labs(rs.r1_doubled - centre);
  double extreme = 0.0, all = 0.0;
  for (long s = 0; s <= total; ++s) {
    all += ways[m][size_t(s)];
    if (std::labs(s - centre) >= observed) extreme += ways[m][size_t(s)];
  }
  return std::min(1.0, extreme / all);
}

MannWhitneyResult mann_whitney_core(const std::vector<double>& x, const std::vector<double>& y,
                                    MannWhitneyMethod method) {
  const double n1 = double(x.size()), n2 = double(y.size());
  const RankSums rs = rank_sums(x, y);
  MannWhitneyResult r;
  r.u1 = rs.u1;
  r.u2 = n1 * n2 - rs.u1;
  // Exact without ties up to 20 a side; with ties up to 8 a side (scipy's bound for its exact
  // method), where the normal approximation is far off and the split of the midranks is cheap.
  const size_t most = std::max(x.size(), y.size());
  const bool exact =
      method == MannWhitneyMethod::kExact || (method == MannWhitneyMethod::kAuto && most <= (rs.ties ? 8u : 20u));
  if (method == MannWhitneyMethod::kExact) {
    if (x.size() * y.size() > 10000)
      throw Error("stats: mann_whitney_u: the exact p-value is limited to n1 * n2 <= 10000, got " +
                  std::to_string(x.size()) + " * " + std::to_string(y.size()) +
                  "; use the asymptotic method");
  }
  if (exact) {
    r.exact = true;
    // Without ties U's distribution is symmetric and the classic recurrence gives it; with ties
    // (times on a checkpoint grid) the split of the midranks does, where the normal approximation
    // is far off for a few trials a side (2 against 2: 0.245, below the least exact p, 1/3).
    r.p_value = rs.ties ? exact_p_with_ties(rs, x.size())
                        : std::min(1.0, 2.0 * exact_cdf(x.size(), y.size(), std::min(r.u1, r.u2)));
    return r;
  }
  const double n = n1 + n2;
  const double mu = n1 * n2 / 2.0;
  const double var = n1 * n2 / 12.0 * ((n + 1.0) - rs.tie_term / (n * (n - 1.0)));
  if (!(var > 0.0)) {  // every value tied: no evidence either way
    r.z = 0.0;
    r.p_value = 1.0;
    return r;
  }
  const double d = r.u1 - mu;
  const double corrected = std::abs(d) <= 0.5 ? 0.0 : d - std::copysign(0.5, d);
  r.z = corrected / std::sqrt(var);
  r.p_value = std::min(1.0, std::erfc(std::abs(r.z) / std::sqrt(2.0)));
  return r;
}

// The standard normal quantile z with P(|Z| <= z) = level, by bisection on erfc (0 < level < 1).
double two_sided_z(double level) {
  double lo = 0.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > 1.0 - level ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Censored times as rank keys: reached ones at their time, censored ones at +infinity.
std::vector<double> rank_keys(const std::vector<CensoredTime>& times, const char* what) {
  std::vector<double> keys;
  keys.reserve(times.size());
  for (size_t i = 0; i < times.size(); ++i) {
    const double s = times[i].seconds;
    if (!std::isfinite(s) || s < 0.0)
      throw Error(std::string("stats: ") + what + ": time " + std::to_string(i) + " is " +
                  number(s) + " s, expected a finite time >= 0");
    keys.push_back(times[i].reached ? s : kInf);
  }
  return keys;
}

void check_two(const std::vector<double>& x, const std::vector<double>& y, const char* what) {
  if (x.empty() || y.empty())
    throw Error(std::string("stats: ") + what + " needs two non-empty samples, got " +
                std::to_string(x.size()) + " and " + std::to_string(y.size()) + " values");
}

}  // namespace

double mean(const std::vector<double>& xs) {
  check_sample(xs, "mean");
  return plain_mean(xs);
}

double sample_std(const std::vector<double>& xs) {
  check_sample(xs, "sample_std", 2);
  return std::sqrt(squared_deviations(xs) / double(xs.size() - 1));
}

double population_std(const std::vector<double>& xs) {
  check_sample(xs, "population_std");
  return std::sqrt(squared_deviations(xs) / double(xs.size()));
}

double median(const std::vector<double>& xs) {
  check_sample(xs, "median");
  return sorted_quantile(sorted(xs), 0.5);
}

double quantile(const std::vector<double>& xs, double q) {
  check_sample(xs, "quantile");
  if (!(q >= 0.0 && q <= 1.0))
    throw Error("stats: quantile: q is " + number(q) + ", expected a number in [0, 1]");
  return sorted_quantile(sorted(xs), q);
}

double interquartile_mean(const std::vector<double>& xs) {
  check_sample(xs, "interquartile_mean");
  const std::vector<double> s = sorted(xs);
  const double n = double(s.size());
  double sum = 0.0;
  for (size_t i = 0; i < s.size(); ++i) {
    // Value i owns [i/n, (i+1)/n]; its weight is the part of that inside [0.25, 0.75].
    const double lo = std::max(double(i) / n, 0.25);
    const double hi = std::min(double(i + 1) / n, 0.75);
    if (hi > lo) sum += (hi - lo) * s[i];
  }
  return sum / 0.5;
}

ConfidenceInterval bootstrap_ci(const std::vector<double>& xs, const Statistic& statistic,
                                uint64_t seed, int resamples, double level) {
  check_sample(xs, "bootstrap_ci");
  if (!statistic) throw Error("stats: bootstrap_ci: no statistic given");
  if (resamples < 1)
    throw Error("stats: bootstrap_ci: resamples is " + std::to_string(resamples) +
                ", expected at least 1 (10000 is customary)");
  if (!(level > 0.0 && level < 1.0))
    throw Error("stats: bootstrap_ci: level is " + number(level) +
                ", expected a number strictly between 0 and 1 (0.95 for a 95% interval)");
  ConfidenceInterval ci;
  ci.level = level;
  ci.estimate = statistic(xs);
  Rng rng(seed);
  const int64_t last = int64_t(xs.size()) - 1;
  std::vector<double> resample(xs.size()), values;
  values.reserve(size_t(resamples));
  for (int b = 0; b < resamples; ++b) {
    for (double& v : resample) v = xs[size_t(rng.integer(0, last))];
    const double stat = statistic(resample);
    if (std::isnan(stat))
      throw Error("stats: bootstrap_ci: the statistic returned NaN on resample " +
                  std::to_string(b));
    values.push_back(stat);
  }
  std::sort(values.begin(), values.end());
  const double alpha = 1.0 - level;
  ci.low = sorted_quantile(values, alpha / 2.0);
  ci.high = sorted_quantile(values, 1.0 - alpha / 2.0);
  return ci;
}

ConfidenceInterval wilson_interval(double successes, double n, double level) {
  if (!(n > 0.0 && std::isfinite(n)))
    throw Error("stats: wilson_interval: n is " + number(n) + ", expected a positive number of draws");
  if (!(successes >= 0.0 && successes <= n))
    throw Error("stats: wilson_interval: " + number(successes) + " successes of " + number(n) + " draws");
  if (!(level > 0.0 && level < 1.0))
    throw Error("stats: wilson_interval: level is " + number(level) + ", expected a number strictly between 0 and 1");
  const double z = two_sided_z(level), z2 = z * z, p = successes / n;
  const double centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
  const double half = z / (1.0 + z2 / n) * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n));
  ConfidenceInterval ci;
  ci.level = level;
  ci.estimate = p;
  ci.low = std::max(0.0, centre - half);
  ci.high = std::min(1.0, centre + half);
  return ci;
}

namespace {

// How many times each of counts.size() units is drawn when as many are drawn with replacement.
void draw_counts(Rng& rng, std::vector<double>& counts) {
  std::fill(counts.begin(), counts.end(), 0.0);
  const int64_t last = int64_t(counts.size()) - 1;
  for (size_t k = 0; k < counts.size(); ++k) counts[size_t(rng.integer(0, last))] += 1.0;
}

void check_cells(const std::vector<RateCell>& cells, int resamples, double level) {
  if (cells.empty()) throw Error("stats: pooled_rate_interval needs at least one cell, got none");
  for (size_t k = 0; k < cells.size(); ++k) {
    const RateCell& c = cells[k];
    if (!(c.episodes > 0.0 && std::isfinite(c.episodes) && c.successes >= 0.0 && c.successes <= c.episodes))
      throw Error("stats: pooled_rate_interval: cell " + std::to_string(k) + " (policy " + std::to_string(c.policy) +
                  ", layout " + std::to_string(c.layout) + ") has " + number(c.successes) + " successes of " +
                  number(c.episodes) + " episodes");
  }
  if (resamples < 1)
    throw Error("stats: pooled_rate_interval: resamples is " + std::to_string(resamples) + ", expected at least 1");
  if (!(level > 0.0 && level < 1.0))
    throw Error("stats: pooled_rate_interval: level is " + number(level) + ", expected a number strictly between 0 and 1");
}

// Cells indexed densely: the policy and layout of each as 0, 1, ... in order of first appearance.
struct DenseCells {
  std::vector<size_t> policy, layout;
  std::vector<double> successes, episodes;
  size_t policies = 0, layouts = 0;
  bool shared = false;  // some layout is met by two or more policies
};
DenseCells dense_cells(const std::vector<RateCell>& cells) {
  DenseCells d;
  std::map<int64_t, size_t> pid, lid;
  std::vector<size_t> first_policy;  // per layout
  for (const RateCell& c : cells) {
    const size_t p = pid.emplace(c.policy, pid.size()).first->second;
    const auto [it, fresh] = lid.emplace(c.layout, lid.size());
    if (fresh) first_policy.push_back(p);
    else if (first_policy[it->second] != p) d.shared = true;
    d.policy.push_back(p);
    d.layout.push_back(it->second);
    d.successes.push_back(c.successes);
    d.episodes.push_back(c.episodes);
  }
  d.policies = pid.size();
  d.layouts = lid.size();
  return d;
}

// The cells summed per policy (keep_policies) or per layout: what a resample that draws only one
// of them needs, in as many cells as there are policies or layouts.
DenseCells collapsed(const DenseCells& d, bool keep_policies) {
  DenseCells c = d;
  const size_t units = keep_policies ? d.policies : d.layouts;
  c.policy.assign(units, 0);
  c.layout.assign(units, 0);
  c.successes.assign(units, 0.0);
  c.episodes.assign(units, 0.0);
  for (size_t k = 0; k < d.policy.size(); ++k) {
    const size_t u = keep_policies ? d.policy[k] : d.layout[k];
    (keep_policies ? c.policy : c.layout)[u] = u;
    c.successes[u] += d.successes[k];
    c.episodes[u] += d.episodes[k];
  }
  return c;
}

}  // namespace

RateInterval pooled_rate_interval(const std::vector<RateCell>& cells, uint64_t seed, int resamples, double level) {
  check_cells(cells, resamples, level);
  const DenseCells all = dense_cells(cells);
  RateInterval r;
  r.policies = int64_t(all.policies);
  r.layouts = int64_t(all.layouts);
  r.by = all.policies == 1 ? Resampled::kLayouts : all.shared ? Resampled::kPoliciesAndLayouts : Resampled::kPolicies;
  const bool draw_policies = r.by != Resampled::kLayouts, draw_layouts = r.by != Resampled::kPolicies;
  const DenseCells d = draw_policies && draw_layouts ? all : collapsed(all, draw_policies);
  double successes = 0.0, episodes = 0.0;
  for (size_t k = 0; k < d.policy.size(); ++k) successes += d.successes[k], episodes += d.episodes[k];
  std::vector<double> wp(d.policies, 1.0), wl(d.layouts, 1.0), values;
  values.reserve(size_t(resamples));
  Rng rng(seed);
  for (int b = 0; b < resamples; ++b) {
    double num = 0.0, den = 0.0;
    for (int attempt = 0; den == 0.0; ++attempt) {
      if (attempt == 1000)
        throw Error("stats: pooled_rate_interval: 1000 resamples in a row drew policies that met none of the "
                    "layouts drawn; the cells are too sparse for a crossed bootstrap");
      if (draw_policies) draw_counts(rng, wp);
      if (draw_layouts) draw_counts(rng, wl);
      num = den = 0.0;
      for (size_t k = 0; k < d.policy.size(); ++k) {
        const double w = wp[d.policy[k]] * wl[d.layout[k]];
        num += w * d.successes[k];
        den += w * d.episodes[k];
      }
    }
    values.push_back(num / den);
  }
  std::sort(values.begin(), values.end());
  const double alpha = 1.0 - level;
  const ConfidenceInterval floor = wilson_interval(successes / episodes * double(d.layouts), double(d.layouts), level);
  r.ci.level = level;
  r.ci.estimate = successes / episodes;
  r.ci.low = std::min(sorted_quantile(values, alpha / 2.0), floor.low);
  r.ci.high = std::max(sorted_quantile(values, 1.0 - alpha / 2.0), floor.high);
  return r;
}

CurveBands curve_bands(const std::vector<std::vector<double>>& values, uint64_t seed, int resamples,
                       double level) {
  if (values.empty()) throw Error("stats: curve_bands needs at least one trial's curve, got none");
  const size_t points = values.front().size();
  for (size_t t = 1; t < values.size(); ++t)
    if (values[t].size() != points)
      throw Error("stats: curve_bands: trial " + std::to_string(t) + " has " +
                  std::to_string(values[t].size()) + " points but trial 0 has " +
                  std::to_string(points) + "; every curve must be on the same grid");
  // One set of resampled trials for the whole curve (each resample a multiset of whole trials, as
  // rliable draws them): with a seed per point, the few distinct resamples of 3 trials fell
  // differently at neighbouring points and the band's edge jumped between them. The draws are
  // bootstrap_ci's with `seed`, so every point's interval is bootstrap_ci(point, seed).
  if (resamples < 1)
    throw Error("stats: curve_bands: resamples is " + std::to_string(resamples) + ", expected at least 1");
  if (!(level > 0.0 && level < 1.0))
    throw Error("stats: curve_bands: level is " + number(level) + ", expected a number strictly between 0 and 1");
  Rng rng(seed);
  const size_t n = values.size();
  std::vector<uint32_t> drawn(size_t(resamples) * n);
  for (uint32_t& i : drawn) i = uint32_t(rng.integer(0, int64_t(n) - 1));
  CurveBands b;
  std::vector<double> v(n), resample(n), iqms(static_cast<size_t>(resamples));
  for (size_t k = 0; k < points; ++k) {
    for (size_t t = 0; t < n; ++t) v[t] = values[t][k];
    b.mean.push_back(mean(v));
    b.std.push_back(population_std(v));
    check_sample(v, "curve_bands");
    ConfidenceInterval ci;
    ci.level = level;
    ci.estimate = interquartile_mean(v);
    for (size_t r = 0; r < size_t(resamples); ++r) {
      for (size_t t = 0; t < n; ++t) resample[t] = v[drawn[r * n + t]];
      iqms[r] = interquartile_mean(resample);
    }
    std::sort(iqms.begin(), iqms.end());
    ci.low = sorted_quantile(iqms, (1.0 - level) / 2.0);
    ci.high = sorted_quantile(iqms, 1.0 - (1.0 - level) / 2.0);
    b.iqm.push_back(ci.estimate);
    b.iqm_low.push_back(ci.low);
    b.iqm_high.push_back(ci.high);
  }
  return b;
}

MannWhitneyResult mann_whitney_u(const std::vector<double>& x, const std::vector<double>& y,
                                 MannWhitneyMethod method) {
  check_two(x, y, "mann_whitney_u");
  check_sample(x, "mann_whitney_u (first sample)");
  check_sample(y, "mann_whitney_u (second sample)");
  return mann_whitney_core(x, y, method);
}

double probability_of_improvement(const std::vector<double>& x, const std::vector<double>& y) {
  check_two(x, y, "probability_of_improvement");
  check_sample(x, "probability_of_improvement (first sample)");
  check_sample(y, "probability_of_improvement (second sample)");
  const double n1n2 = double(x.size()) * double(y.size());
  return (n1n2 - rank_sums(x, y).u1) / n1n2;
}

double fraction_reached(const std::vector<CensoredTime>& times) {
  if (times.empty()) throw Error("stats: fraction_reached needs at least one trial, got none");
  size_t reached = 0;
  for (const auto& t : times) reached += t.reached ? 1 : 0;
  return double(reached) / double(times.size());
}

std::vector<double> censored_values(const std::vector<CensoredTime>& times) {
  rank_keys(times, "censored_values");  // validates every time
  std::vector<double> out;
  out.reserve(times.size());
  for (const auto& t : times) out.push_back(t.seconds);
  return out;
}

std::vector<double> censored_far_values(const std::vector<CensoredTime>& times) {
  rank_keys(times, "censored_far_values");  // validates every time
  // Far above any time in seconds, and far enough below the largest double that sums of a
  // hundred million of them stay finite.
  constexpr double kFar = 1e200;
  std::vector<double> out;
  out.reserve(times.size());
  for (const auto& t : times) out.push_back(t.reached ? t.seconds : kFar);
  return out;
}

MannWhitneyResult mann_whitney_u_censored(const std::vector<CensoredTime>& x,
                                          const std::vector<CensoredTime>& y,
                                          MannWhitneyMethod method) {
  const std::vector<double> kx = rank_keys(x, "mann_whitney_u (first sample)");
  const std::vector<double> ky = rank_keys(y, "mann_whitney_u (second sample)");
  check_two(kx, ky, "mann_whitney_u");
  return mann_whitney_core(kx, ky, method);
}

double probability_of_improvement_censored(const std::vector<CensoredTime>& x,
                                           const std::vector<CensoredTime>& y) {
  const std::vector<double> kx = rank_keys(x, "probability_of_improvement (first sample)");
  const std::vector<double> ky = rank_keys(y, "probability_of_improvement (second sample)");
  check_two(kx, ky, "probability_of_improvement");
  const double n1n2 = double(kx.size()) * double(ky.size());
  return (n1n2 - rank_sums(kx, ky).u1) / n1n2;
}

std::string format_min_sec(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0)
    throw Error("stats: format_min_sec: " + number(seconds) +
                " s is not a duration; expected a finite number of seconds >= 0");
  if (seconds >= 9.0e15)
    throw Error("stats: format_min_sec: " + number(seconds) + " s is too long to format");
  const long long total = std::llround(seconds);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%lld:%02lld", total / 60, total % 60);
  return buf;
}

double percent_improvement(double baseline, double value) {
  if (!std::isfinite(baseline) || !(baseline > 0.0))
    throw Error("stats: percent_improvement: the baseline is " + number(baseline) +
                ", expected a positive finite number");
  if (!std::isfinite(value))
    throw Error("stats: percent_improvement: the value is " + number(value) +
                ", expected a finite number");
  return 100.0 * (baseline - value) / baseline;
}

CurveGrid curve_grid(const std::vector<std::vector<std::pair<double, double>>>& trials, int points, bool log_x) {
  CurveGrid g;
  double lo = -1, hi = -1;
  for (const auto& tr : trials) {
    if (tr.empty()) continue;
    lo = std::max(lo, tr.front().first);
    hi = std::max(hi, tr.back().first);
  }
  if (hi < 0 || points < 2) return g;
  if (log_x && lo <= 0) {
    // The first positive checkpoint time of the trial whose first one is latest.
    lo = hi;
    for (const auto& tr : trials)
      for (const auto& [t, v] : tr)
        if (t > 0) {
          lo = std::min(lo, t);
          break;
        }
  }
  if (hi <= lo) {
    g.t = {lo};
  } else {
    for (int k = 0; k < points; ++k) {
      const double f = double(k) / double(points - 1);
      g.t.push_back(log_x ? lo * std::pow(hi / lo, f) : lo + (hi - lo) * f);
    }
  }
  for (const auto& tr : trials) {
    if (tr.empty()) continue;
    std::vector<double> v;
    for (double t : g.t) {
      if (t <= tr.front().first) {
        v.push_back(tr.front().second);
        continue;
      }
      if (t >= tr.back().first) {
        v.push_back(tr.back().second);
        continue;
      }
      const auto it = std::lower_bound(tr.begin(), tr.end(), t,
                                       [](const std::pair<double, double>& p, double x) { return p.first < x; });
      const auto& b = *it;
      const auto& a = *(it - 1);
      const double w = b.first > a.first ? (t - a.first) / (b.first - a.first) : 1.0;
      v.push_back(a.second + w * (b.second - a.second));
    }
    g.values.push_back(std::move(v));
  }
  return g;
}

}  // namespace roger
