// alp_gmm.cpp: ALP-GMM (Portelas et al., 2019, "Teacher algorithms for curriculum learning of
// Deep RL in continuously parameterized environments"). Each episode's absolute learning progress
// (ALP) is |success - success of the nearest earlier task|; every fit_every episodes Gaussian
// mixtures of 2..k_max components are fitted to the recent (task, ALP) pairs in the unit cube and
// the one of least AIC is kept; a task is drawn from a component chosen in proportion to its mean
// ALP, or uniformly with probability random_share (and always before the first fit).
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>

#include "teach/teach_internal.h"

namespace roger::teach_detail {
namespace {

using json = nlohmann::json;

class AlpGmmTeacher final : public Teacher {
 public:
  AlpGmmTeacher(const TeacherSpec& spec, const TaskSpace& space, uint64_t seed)
      : spec_(spec), space_(space), rng_(seed), dims_(int(space.size())) {}
  std::string kind() const override { return "alp_gmm"; }

  TaskPick next() override {
    if (!fitted_ || rng_.uniform() < spec_.random_share) return {space_.sample(rng_), {}, std::nullopt};
    // A component in proportion to its mean ALP (its last coordinate).
    double total = 0.0;
    for (const Gaussian& g : mix_.parts) total += std::max(0.0, g.mean[dims_]);
    if (!(total > 0.0)) return {space_.sample(rng_), {}, std::nullopt};  // no progress anywhere
    double r = rng_.uniform() * total;
    size_t pick = 0;
    for (; pick + 1 < mix_.parts.size(); ++pick)
      if ((r -= std::max(0.0, mix_.parts[pick].mean[dims_])) < 0.0) break;
    const Eigen::VectorXd u = sample_marginal(mix_.parts[pick], dims_, rng_);
    return {space_.from_unit(std::vector<double>(u.data(), u.data() + dims_)), {}, std::nullopt};
  }

  void record(const TaskOutcome& o) override {
    const std::vector<double> u = space_.to_unit(o.task);
    const double outcome = o.success ? 1.0 : 0.0;
    pairs_.push_back({u, std::abs(outcome - nearest_outcome(u, outcome))});
    if (int(pairs_.size()) > spec_.history) pairs_.pop_front();
    tasks_.push_back(u);
    outcomes_.push_back(outcome);
    if (int(tasks_.size()) % spec_.fit_every == 0) fit();
  }

  // Recorded to six decimals: a fit's 0.9999999999999374 and 6.9e-218 read as the 1 and 0 they
  // are (the teacher itself keeps the full values).
  json state() const override {
    const auto six = [](double x) { return std::round(x * 1e6) / 1e6 + 0.0; };  // + 0.0: no -0
    json parts = json::array();
    for (const Gaussian& g : mix_.parts) {
      std::vector<double> mean(g.mean.data(), g.mean.data() + dims_), sd, shown;
      for (int i = 0; i < dims_; ++i) sd.push_back(six(std::sqrt(g.cov(i, i))));
      for (double m : mean) shown.push_back(six(m));
      parts.push_back({{"weight", six(g.weight)}, {"alp", six(g.mean[dims_])}, {"mean", shown}, {"std", sd},
                       {"task", space_.to_json(space_.from_unit(mean))}});
    }
    std::vector<std::string> names;
    for (const auto& d : space_.dims()) names.push_back(d.name);
    double alp = 0.0;
    for (const auto& p : pairs_) alp += p.second;
    return {{"kind", kind()}, {"episodes", tasks_.size()}, {"fits", fits_}, {"dims", names},
            {"mean_alp", pairs_.empty() ? 0.0 : six(alp / double(pairs_.size()))}, {"components", parts}};
  }

 private:
  // The outcome of the nearest earlier task in the unit cube (the latest among equals: on int and
  // choice axes the same task's last try, so a task that failed once and succeeds since stops
  // showing progress; found by a probe: compared with its first try, it showed progress 1 for
  // good); this episode's own outcome when there is none, so the first ALP is 0.
  double nearest_outcome(const std::vector<double>& u, double fallback) const {
    double best = std::numeric_limits<double>::infinity(), out = fallback;
    for (size_t k = 0; k < tasks_.size(); ++k) {
      double d2 = 0.0;
      for (int i = 0; i < dims_; ++i) d2 += (tasks_[k][size_t(i)] - u[size_t(i)]) * (tasks_[k][size_t(i)] - u[size_t(i)]);
      if (d2 <= best) best = d2, out = outcomes_[k];
    }
    return out;
  }

  void fit() {
    Eigen::MatrixXd x(Eigen::Index(pairs_.size()), dims_ + 1);
    for (size_t r = 0; r < pairs_.size(); ++r) {
      for (int i = 0; i < dims_; ++i) x(Eigen::Index(r), i) = pairs_[r].first[size_t(i)];
      x(Eigen::Index(r), dims_) = pairs_[r].second;
    }
    mix_ = best_mixture(x, 2, spec_.k_max, rng_, &fits_by_k_);
    fitted_ = true;
    ++fits_;
  }

  TeacherSpec spec_;
  TaskSpace space_;
  Rng rng_;
  int dims_;
  std::vector<std::vector<double>> tasks_;                 // every episode's task, unit cube
  std::vector<double> outcomes_;                           // and its outcome
  std::deque<std::pair<std::vector<double>, double>> pairs_;  // recent (task, ALP)
  Mixture mix_;
  std::vector<Mixture> fits_by_k_;  // each k's last fit, where the next starts (warm)
  bool fitted_ = false;
  int fits_ = 0;
};

}  // namespace

std::unique_ptr<Teacher> make_alp_gmm(const TeacherSpec& spec, const TaskSpace& space, uint64_t seed) {
  return std::make_unique<AlpGmmTeacher>(spec, space, seed);
}

}  // namespace roger::teach_detail
