// gmm.cpp: Gaussian mixtures fitted by expectation-maximisation, chosen by AIC (for ALP-GMM).
// Small problems (a few hundred points in a handful of dimensions), fitted between episodes.
#include <algorithm>
#include <cmath>
#include <limits>

#include "teach/teach_internal.h"

namespace roger::teach_detail {
namespace {

constexpr double kLog2Pi = 1.8378770664093453;

// Means, covariances and weights from the responsibilities (one column per component). Plain
// loops over the matrices' storage (column-major): they are a few hundred rows of a handful of
// columns, where Eigen's general kernels (and its checked element access: the build keeps
// asserts) cost more than the arithmetic.
void maximise(const Eigen::MatrixXd& x, const Eigen::MatrixXd& resp, double reg, std::vector<Gaussian>& parts) {
  const int n = int(x.rows()), d = int(x.cols());
  const double* xs = x.data();
  std::vector<double> c(static_cast<size_t>(d)), mean(static_cast<size_t>(d)), cov(static_cast<size_t>(d * d));
  for (int j = 0; j < int(parts.size()); ++j) {
    Gaussian& g = parts[size_t(j)];
    const double* r = resp.data() + size_t(j) * size_t(n);
    double nk = 1e-12;
    std::fill(mean.begin(), mean.end(), 0.0);
    for (int i = 0; i < n; ++i) {
      nk += r[i];
      for (int a = 0; a < d; ++a) mean[size_t(a)] += r[i] * xs[a * n + i];
    }
    for (double& m : mean) m /= nk;
    std::fill(cov.begin(), cov.end(), 0.0);
    for (int i = 0; i < n; ++i) {
      for (int a = 0; a < d; ++a) c[size_t(a)] = xs[a * n + i] - mean[size_t(a)];
      for (int a = 0; a < d; ++a)
        for (int b = 0; b <= a; ++b) cov[size_t(a * d + b)] += r[i] * c[size_t(a)] * c[size_t(b)];
    }
    g.weight = nk / double(n);
    g.mean = Eigen::Map<const Eigen::VectorXd>(mean.data(), d);
    g.cov.resize(d, d);
    for (int a = 0; a < d; ++a)
      for (int b = 0; b <= a; ++b) g.cov(a, b) = g.cov(b, a) = cov[size_t(a * d + b)] / nk + (a == b ? reg : 0.0);
    g.chol = Eigen::LLT<Eigen::MatrixXd>(g.cov).matrixL();
    g.log_det = 2.0 * g.chol.diagonal().array().log().sum();
  }
}

// Responsibilities from the components; returns the log-likelihood of x.
double expect(const Eigen::MatrixXd& x, const std::vector<Gaussian>& parts, Eigen::MatrixXd& resp) {
  const int n = int(x.rows()), d = int(x.cols()), k = int(parts.size());
  const double* xs = x.data();
  double* rs = resp.data();
  std::vector<double> z(static_cast<size_t>(d));
  for (int j = 0; j < k; ++j) {
    const Gaussian& g = parts[size_t(j)];
    const double* mu = g.mean.data();
    const double* l = g.chol.data();  // column-major: L(a, b) = l[b * d + a]
    const double base = std::log(std::max(g.weight, 1e-300)) - 0.5 * (d * kLog2Pi + g.log_det);
    for (int i = 0; i < n; ++i) {
      double m = 0.0;  // |L^-1 (x - mean)|^2 by forward substitution
      for (int a = 0; a < d; ++a) {
        double v = xs[a * n + i] - mu[a];
        for (int b = 0; b < a; ++b) v -= l[b * d + a] * z[size_t(b)];
        z[size_t(a)] = v / l[a * d + a];
        m += z[size_t(a)] * z[size_t(a)];
      }
      rs[j * n + i] = base - 0.5 * m;  // log p(x_i, j) for now
    }
  }
  double ll = 0.0;
  for (int i = 0; i < n; ++i) {
    double top = rs[i];
    for (int j = 1; j < k; ++j) top = std::max(top, rs[j * n + i]);
    double sum = 0.0;
    for (int j = 0; j < k; ++j) sum += rs[j * n + i] = std::exp(rs[j * n + i] - top);
    for (int j = 0; j < k; ++j) rs[j * n + i] /= sum;
    ll += top + std::log(sum);
  }
  return ll;
}

// k-means++ centres (row indices of x), drawn from rng.
std::vector<int> seed_centres(const Eigen::MatrixXd& x, int k, Rng& rng) {
  const int n = int(x.rows());
  std::vector<int> centres{int(rng.integer(0, n - 1))};
  Eigen::VectorXd d2 = (x.rowwise() - x.row(centres[0])).rowwise().squaredNorm();
  while (int(centres.size()) < k) {
    const double total = d2.sum();
    int pick = 0;
    if (!(total > 0.0)) {
      pick = int(rng.integer(0, n - 1));  // every point on a centre: any will do
    } else {
      double r = rng.uniform() * total;
      for (pick = 0; pick < n - 1 && (r -= d2[pick]) >= 0.0; ++pick) {}
    }
    centres.push_back(pick);
    d2 = d2.cwiseMin((x.rowwise() - x.row(pick)).rowwise().squaredNorm());
  }
  return centres;
}

}  // namespace

Mixture fit_mixture(const Eigen::MatrixXd& x, int k, Rng& rng, const Mixture* start, double reg, int max_iter,
                    double tol) {
  const int n = int(x.rows()), d = int(x.cols());
  Mixture m;
  Eigen::MatrixXd resp = Eigen::MatrixXd::Zero(n, k);
  // Warm from the last fit of this k, on data that shares most of its points, unless a component
  // of it holds less than a point: EM never revives an empty one (found by a probe: a component
  // whose one point left the history stayed, weight 0 at the origin, fit after fit).
  const bool warm = start && int(start->parts.size()) == k && start->parts.front().mean.size() == d &&
                    std::all_of(start->parts.begin(), start->parts.end(),
                                [&](const Gaussian& g) { return g.weight * double(n) >= 1.0; });
  if (warm) {
    m.parts = start->parts;
  } else {
    // Cold: the hard assignment to the nearest k-means++ centre.
    m.parts.resize(size_t(k));
    const std::vector<int> centres = seed_centres(x, k, rng);
    for (int i = 0; i < n; ++i) {
      int best = 0;
      double best_d = std::numeric_limits<double>::infinity();
      for (int j = 0; j < k; ++j) {
        const double dj = (x.row(i) - x.row(centres[size_t(j)])).squaredNorm();
        if (dj < best_d) best_d = dj, best = j;
      }
      resp(i, best) = 1.0;
    }
    maximise(x, resp, reg, m.parts);
  }
  double previous = -std::numeric_limits<double>::infinity();
  for (m.iterations = 0; m.iterations < max_iter; ++m.iterations) {
    m.log_likelihood = expect(x, m.parts, resp);
    if (m.log_likelihood - previous < tol * n) break;
    previous = m.log_likelihood;
    maximise(x, resp, reg, m.parts);
  }
  if (m.iterations == max_iter) m.log_likelihood = expect(x, m.parts, resp);  // of the last maximisation
  const double free = double(k) * (d + d * (d + 1) / 2.0) + double(k - 1);
  m.aic = 2.0 * free - 2.0 * m.log_likelihood;
  return m;
}

Mixture best_mixture(const Eigen::MatrixXd& x, int k_min, int k_max, Rng& rng, std::vector<Mixture>* last) {
  Mixture best;
  bool any = false;
  if (last && int(last->size()) <= k_max) last->resize(size_t(k_max) + 1);
  for (int k = k_min; k <= std::min<int>(k_max, int(x.rows())); ++k) {
    Mixture m = fit_mixture(x, k, rng, last ? &(*last)[size_t(k)] : nullptr);
    if (last) (*last)[size_t(k)] = m;
    if (!any || m.aic < best.aic) best = std::move(m), any = true;
  }
  if (!any) best = fit_mixture(x, 1, rng);
  return best;
}

Eigen::VectorXd sample_marginal(const Gaussian& g, int dims, Rng& rng) {
  const Eigen::MatrixXd cov = g.cov.topLeftCorner(dims, dims);
  const Eigen::MatrixXd l = Eigen::LLT<Eigen::MatrixXd>(cov).matrixL();
  Eigen::VectorXd z(dims);
  for (int i = 0; i < dims; ++i) z[i] = rng.normal();
  return g.mean.head(dims) + l * z;
}

}  // namespace roger::teach_detail
