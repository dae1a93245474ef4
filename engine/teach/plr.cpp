// plr.cpp: Prioritized Level Replay (Jiang, Grefenstette and Rocktaschel, 2021). A level is a task
// with a world seed. With probability `replay` (once a level has been seen) a seen level is
// replayed, drawn from P = (1 - staleness) P_S + staleness P_C, where P_S is rank-based,
// h(S_i)^(1/temperature) with h = 1/rank of the level's score, and P_C favours the levels unseen
// the longest (episodes since their last draw); otherwise a new level: a uniform task in the
// episode's own world. A level's score is its last episode's mean |TD error| (or 1 - success).
#include <algorithm>
#include <cmath>
#include <numeric>

#include "teach/teach_internal.h"

namespace roger::teach_detail {
namespace {

using json = nlohmann::json;

class PlrTeacher final : public Teacher {
 public:
  PlrTeacher(const TeacherSpec& spec, const TaskSpace& space, uint64_t seed)
      : spec_(spec), space_(space), rng_(seed) {}
  std::string kind() const override { return "plr"; }

  TaskPick next() override {
    pending_ = -1;
    if (!levels_.empty() && rng_.uniform() < spec_.replay) {
      pending_ = draw_replay();
      ++replays_;
      const Level& l = levels_[size_t(pending_)];
      return {l.task, {}, l.seed};
    }
    return {space_.sample(rng_), {}, std::nullopt};
  }

  void record(const TaskOutcome& o) override {
    ++episodes_;
    const double score = spec_.score_td ? o.td_error : 1.0 - (o.success ? 1.0 : 0.0);
    if (pending_ >= 0) {
      Level& l = levels_[size_t(pending_)];
      l.score = score, l.last = episodes_, ++l.visits;
      return;
    }
    Level fresh{o.task, o.world_seed, score, episodes_, 1, next_order_++};
    if (int(levels_.size()) < spec_.buffer) {
      levels_.push_back(std::move(fresh));
      return;
    }
    // A full buffer: the new level takes the place of the lowest-scored one if it scores higher.
    auto low = std::min_element(levels_.begin(), levels_.end(),
                                [](const Level& a, const Level& b) { return a.score < b.score; });
    if (score > low->score) *low = std::move(fresh);
  }

  json state() const override {
    std::vector<size_t> order = by_rank();
    json top = json::array();
    for (size_t k = 0; k < order.size() && k < 5; ++k) {
      const Level& l = levels_[order[k]];
      top.push_back({{"task", space_.to_json(l.task)}, {"seed", l.seed}, {"score", l.score}, {"visits", l.visits}});
    }
    return {{"kind", kind()}, {"episodes", episodes_}, {"levels", levels_.size()}, {"replays", replays_},
            {"top", top}};
  }

 private:
  struct Level {
    TaskPoint task;
    uint64_t seed = 0;
    double score = 0.0;
    int last = 0;      // the episode count when it was last played
    int visits = 0;
    int64_t order = 0; // when it was first played (ties of score rank the older first)
  };

  // Level indices from the highest score down.
  std::vector<size_t> by_rank() const {
    std::vector<size_t> idx(levels_.size());
    std::iota(idx.begin(), idx.end(), size_t(0));
    std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) {
      if (levels_[a].score != levels_[b].score) return levels_[a].score > levels_[b].score;
      return levels_[a].order < levels_[b].order;
    });
    return idx;
  }

  int draw_replay() {
    const std::vector<size_t> order = by_rank();
    const size_t n = levels_.size();
    std::vector<double> ps(n, 0.0), pc(n, 0.0);
    double sum_s = 0.0, sum_c = 0.0;
    for (size_t r = 0; r < n; ++r) {
      ps[order[r]] = std::pow(1.0 / double(r + 1), 1.0 / spec_.temperature);
      sum_s += ps[order[r]];
    }
    for (size_t i = 0; i < n; ++i) sum_c += pc[i] = double(episodes_ - levels_[i].last);
    double r = rng_.uniform();
    for (size_t i = 0; i < n; ++i) {
      const double p = (1.0 - spec_.staleness) * ps[i] / sum_s +
                       spec_.staleness * (sum_c > 0.0 ? pc[i] / sum_c : 1.0 / double(n));
      if ((r -= p) < 0.0) return int(i);
    }
    return int(order.front());  // rounding left a sliver: the top level
  }

  TeacherSpec spec_;
  TaskSpace space_;
  Rng rng_;
  std::vector<Level> levels_;
  int pending_ = -1;  // the level the last next() replayed, -1 for a new one
  int episodes_ = 0, replays_ = 0;
  int64_t next_order_ = 0;
};

}  // namespace

std::unique_ptr<Teacher> make_plr(const TeacherSpec& spec, const TaskSpace& space, uint64_t seed) {
  return std::make_unique<PlrTeacher>(spec, space, seed);
}

}  // namespace roger::teach_detail
