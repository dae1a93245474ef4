// teach_internal.h: what the files of teach/ share (private to the folder): the Gaussian mixtures
// ALP-GMM fits (gmm.cpp) and the teachers each file defines (teachers.cpp: random, sequence,
// LCAS and make_teacher; alp_gmm.cpp; plr.cpp).
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Dense>

#include "core/rng.h"
#include "teach/teach.h"

namespace roger::teach_detail {

// One component of a mixture, with its covariance's Cholesky factor.
struct Gaussian {
  double weight = 0.0;
  Eigen::VectorXd mean;
  Eigen::MatrixXd cov;
  Eigen::MatrixXd chol;   // lower-triangular L, cov = L L^T
  double log_det = 0.0;   // log |cov|
};

// A Gaussian mixture fitted by expectation-maximisation.
struct Mixture {
  std::vector<Gaussian> parts;
  double log_likelihood = 0.0;
  double aic = 0.0;       // 2 (free parameters) - 2 log-likelihood
  int iterations = 0;
};

// Fits k full-covariance components to the rows of x, then EM until the mean log-likelihood gains
// less than `tol` per point (scikit-learn's default) or `max_iter` iterations. EM starts from
// `start` when it is a mixture of k components over as many columns (warm: a teacher refits every
// few episodes on data that mostly overlaps, and EM then needs a few iterations instead of tens)
// and each of its components holds at least a point's weight of x (EM never revives an empty one),
// else from k-means++ seeds drawn from rng. `reg` is added to every covariance's diagonal (tasks
// on a discrete axis coincide: without it a component collapses onto one value). Deterministic for
// the same inputs, start and rng.
Mixture fit_mixture(const Eigen::MatrixXd& x, int k, Rng& rng, const Mixture* start = nullptr, double reg = 1e-3,
                    int max_iter = 100, double tol = 1e-3);

// The mixture of k_min..k_max components (each at most the number of rows) with the least AIC.
// `last` (when given) holds each k's previous fit, the start of this one, and receives the new.
Mixture best_mixture(const Eigen::MatrixXd& x, int k_min, int k_max, Rng& rng, std::vector<Mixture>* last = nullptr);

// A draw from component g's marginal over its first `dims` coordinates.
Eigen::VectorXd sample_marginal(const Gaussian& g, int dims, Rng& rng);

std::unique_ptr<Teacher> make_alp_gmm(const TeacherSpec& spec, const TaskSpace& space, uint64_t seed);
std::unique_ptr<Teacher> make_plr(const TeacherSpec& spec, const TaskSpace& space, uint64_t seed);

}  // namespace roger::teach_detail
