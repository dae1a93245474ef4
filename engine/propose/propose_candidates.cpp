// propose_candidates.cpp: the candidate curricula a probe suggests, and their Lua text.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "propose/propose_internal.h"

namespace roger::propose_detail {

namespace {

// A proposal made with ROGER_HOME set loads with it alone (docs/propose.md): its commands say so
// (found by a probe: run as its header wrote them, they failed with "module 'mine' not found").
std::string home_prefix() {
  const char* home = std::getenv("ROGER_HOME");
  return home && *home ? "ROGER_HOME=" + shell_word(home) + " " : "";
}

std::string home_note() {
  return home_prefix().empty() ? "" : "-- Proposed with ROGER_HOME set: it loads with the same ROGER_HOME.\n";
}

// A Lua string literal.
std::string lua_quote(const std::string& s) {
  std::string q = "\"";
  for (char ch : s) {
    if (ch == '"' || ch == '\\') q += '\\';
    q += ch == '\n' ? ' ' : ch;
  }
  return q + "\"";
}

// A name made of letters, digits and underscores ("phi4 <| phi2" -> "phi4_phi2").
std::string ident(const std::string& s) {
  std::string r;
  for (char ch : s) {
    const bool word = std::isalnum(static_cast<unsigned char>(ch)) != 0;
    if (word) r += ch;
    else if (!r.empty() && r.back() != '_') r += '_';
  }
  while (!r.empty() && r.back() == '_') r.pop_back();
  return r.empty() ? "x" : r;
}

std::string percent(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.0f%%", 100 * x);
  return b;
}

// Passing checkpoints in a row of one greedy policy after which a subgoal stage stops when the task
// has no stop rule of its own (stop_after = 0, as SG: the paper trains it to the end of its budget
// to compare learning curves). A subgoal stage is a means: once its skill reaches the subgoal, more
// training only spends the trial's cap, which the task then never gets. Five passes of one policy,
// not one: curricula/lib/paper_stages.lua measured that a policy stopped on fewer passes (20
// held-out seeds) can be a weak skill that stalls the stage built on it. A task with a rule of its
// own (T: 5 of one policy) keeps it for its subgoal stages: its author's meaning of learned.
constexpr int kSubgoalStopAfter = 5;

// A learned subgoal stage of a candidate: reach CONV of `goal` with `actions` (Lua expressions).
struct SubStage {
  std::string goal;                   // the action's name in Psi
  std::vector<std::string> actions;   // Lua expressions
  std::string skill;                  // the learned skill's name
  std::vector<std::string> names;     // the actions' names, for people
};

// Builds one candidate's Lua text.
struct LuaCandidate {
  const TaskRef& task;
  std::vector<std::string> defs;      // local definitions (sequences)
  std::vector<SubStage> subs;
  std::vector<std::string> final_actions, final_names;

  static std::string act(const std::string& name) { return "A[" + lua_quote(name) + "]"; }
  void add_action(const std::string& name) { final_actions.push_back(act(name)), final_names.push_back(name); }
  std::string params() const { return task.context_params ? ", params = params" : ""; }
  std::string list(const std::vector<std::string>& xs) const {
    std::string s = "{ ";
    for (size_t i = 0; i < xs.size(); ++i) s += (i ? ", " : "") + xs[i];
    return s + " }";
  }

  // What the subgoal stages are built from: the task itself when it has a stop rule, else a copy of
  // it (written to `o`) whose checkpoints stop after kSubgoalStopAfter passes of one policy.
  std::string subgoal_task(std::ostream& o) const {
    if (subs.empty() || task.stop_after > 0) return "task";
    o << "\n-- The subgoal stages stop once they have learned their subgoal (" << kSubgoalStopAfter
      << " passing checkpoints in a row\n-- of one greedy policy): the task trains to the end of its budget "
      << "(stop_after = 0), and a\n-- subgoal stage copying that would spend what the task needs.\n"
      << "local subgoal_task = propose.task(" << lua_quote(task.module) << ", " << lua_quote(task.stage)
      << (task.scenario.empty() ? std::string() : ", { scenario = " + lua_quote(task.scenario) + " }") << ")\n"
      << "subgoal_task.checkpoints = {}\n"
      << "for key, value in pairs(task.checkpoints or {}) do subgoal_task.checkpoints[key] = value end\n"
      << "subgoal_task.checkpoints.stop_after, subgoal_task.checkpoints.settle = " << kSubgoalStopAfter << ", true\n";
    return "subgoal_task";
  }

  std::string text(const Candidate& c, const std::vector<std::string>& base_psi) const {
    std::ostringstream o;
    o << "-- " << c.id << ".lua: a curriculum proposed by roger propose for stage '" << task.stage << "' of '"
      << task.module << "'\n-- (" << task.command << "; docs/propose.md).\n--\n"
      << "-- Candidate " << c.id << " (" << c.kind << "): " << c.summary << "\n-- Why: " << c.why << "\n--\n"
      << home_note() << "--   " << home_prefix() << "roger check <this file>\n--   " << home_prefix()
      << "roger train <this file> --stage " << task.stage << " --context P --seed 1 --out out/" << task.stage << "-P\n"
      << "local propose = require(\"lib.propose\")\n";
    if (!task.scenario.empty())
      o << "-- The scenario as the curriculum resolved it: a path relative to the file that writes the stage\n"
        << "-- would be looked for beside lib/propose.lua, which writes the stages here.\n";
    o << "local task = propose.task(" << lua_quote(task.module) << ", " << lua_quote(task.stage)
      << (task.scenario.empty() ? std::string() : ", { scenario = " + lua_quote(task.scenario) + " }")
      << ")  -- scenario, reward, absorbing predicate, learner\n"
      << "local A = propose.actions(task, " << lua_quote(task.context) << ")  -- the starting Psi, by name\n";
    // The starting context's body or senses, which the probe trained: every context keeps them.
    if (task.context_params)
      o << "local params = propose.params(task, " << lua_quote(task.context)
        << ")  -- its scenario parameters (body, senses)\n";
    for (const auto& d : defs) o << d;
    const std::string sub_task = subgoal_task(o);
    for (const auto& s : subs)
      o << "\n-- A subgoal stage: reach CONV of '" << s.goal << "' with the actions that reach it in the\n"
        << "-- probe's successful episodes; its greedy policy becomes the skill " << s.skill << ".\n"
        << "local " << ident("stage_to_" + s.goal) << " = propose.stage(" << sub_task << ", {\n"
        << "  name = " << lua_quote(task.stage + "_to_" + ident(s.goal)) << ",\n"
        << "  description = " << lua_quote("reach CONV of " + s.goal + " (a subgoal of " + task.stage + ")") << ",\n"
        << "  goal = " << act(s.goal) << ",\n"
        << "  contexts = { { name = \"P\", actions = " << list(s.actions) << params() << " } },\n"
        << "  skill = { name = " << lua_quote(s.skill) << ", context = \"P\" },\n})\n"
        << "local " << ident(s.skill) << " = roger.learned(" << lua_quote(s.skill) << ")\n";
    std::vector<std::string> base;
    for (const auto& n : base_psi) base.push_back(act(n));
    o << "\nreturn {\n  name = " << lua_quote(task.stage + "_proposed") << ",\n  description = "
      << lua_quote("stage " + task.stage + " of " + task.module + ", candidate " + c.id + ": " + c.summary) << ",\n"
      << "  stages = {\n";
    for (const auto& s : subs) o << "    " << ident("stage_to_" + s.goal) << ",\n";
    o << "    propose.stage(task, {\n      name = " << lua_quote(task.stage) << ",\n      contexts = {\n"
      << "        { name = \"P\", actions = " << list(final_actions) << params() << " },  -- the proposal\n"
      << "        { name = " << lua_quote(task.context) << ", actions = " << list(base) << params()
      << " },  -- the starting Psi\n      },\n    }),\n  },\n}\n";
    return o.str();
  }
};

// The subgoals that converge while they run themselves, in the order the successful episodes
// reach them: the steps of a sequence. A controller that converges while another runs (a grasp
// keeper converging as the grasp closes) is a side effect, not a step to run.
std::vector<int> subgoal_path(const ProbeSummary& s) {
  std::vector<int> path;
  for (const auto& g : s.subgoals)
    if (g.achiever == g.action && (path.empty() || path.back() != g.action)) path.push_back(g.action);
  return path;
}

bool contains(const std::vector<int>& v, int x) { return std::find(v.begin(), v.end(), x) != v.end(); }

}  // namespace

namespace {

// The generator's state: the probe, and the candidates so far (distinct by content).
struct Generator {
  const TaskRef& task;
  const ProbeStats& probe;
  const ProbeSummary& s;
  std::vector<CandidateSpec> out;
  std::vector<std::string> seen;

  const std::string& name(int a) const { return probe.psi[size_t(a)]; }
  std::string names(const std::vector<int>& as) const {
    std::string r;
    for (int a : as) r += (r.empty() ? "" : ", ") + name(a);
    return r;
  }
  std::string subgoal_why(const Subgoal& g) const {
    char b[256];
    std::snprintf(b, sizeof b, "CONV of '%s' is reached in %s of the %zu successful probe episodes (median decision %.1f), most often while '%s' runs",
                  name(g.action).c_str(), percent(g.share).c_str(), probe.successes.size(), g.order,
                  g.achiever >= 0 ? name(g.achiever).c_str() : "?");
    return b;
  }

  void emit(LuaCandidate& lc, const std::string& kind, const std::string& why) {
    std::string signature;
    for (const auto& d : lc.defs) signature += d;
    for (const auto& sub : lc.subs) signature += sub.goal + "|" + lc.list(sub.actions);
    signature += lc.list(lc.final_actions);
    if (std::find(seen.begin(), seen.end(), signature) != seen.end()) return;
    seen.push_back(signature);
    CandidateSpec spec;
    Candidate& c = spec.c;
    c.id = "C" + std::to_string(out.size() + 1);
    c.kind = kind;
    c.psi = lc.final_names;
    c.summary = "Psi = {" + [&] { std::string r; for (const auto& x : c.psi) r += (r.empty() ? "" : ", ") + x; return r; }() + "}";
    if (!lc.subs.empty()) {
      std::string subs;
      for (const auto& sub : lc.subs) {
        std::string acts;
        for (const auto& a : sub.names) acts += (acts.empty() ? "" : ", ") + a;
        subs += (subs.empty() ? "" : ", then ") + sub.skill + " learned first from {" + acts + "}";
      }
      c.summary += ", " + subs;
    }
    c.why = why;
    spec.lua = lc.text(c, probe.psi);
    out.push_back(std::move(spec));
  }

  // The sequence of `steps`: its definition added to lc, its name returned.
  std::string sequence(LuaCandidate& lc, const std::vector<int>& steps) const {
    std::string id = "Seq";
    for (int a : steps) id += "_" + ident(name(a));
    std::vector<std::string> acts;
    for (int a : steps) acts.push_back(LuaCandidate::act(name(a)));
    lc.defs.push_back("\n-- Runs " + names(steps) + " in the order the successful episodes converge them.\nlocal " + id +
                      " = roger.sequence(" + lua_quote(id) + ", " + lc.list(acts) + ")\n");
    return id;
  }

  // Psi with `members` replaced by the sequence of them (put first), without the actions `pruned`.
  void macro(const std::vector<int>& members, const std::vector<int>& pruned) {
    LuaCandidate lc{task, {}, {}, {}, {}};
    const std::string seq = sequence(lc, members);
    lc.final_actions.push_back(seq), lc.final_names.push_back(seq);
    for (int a = 0; a < int(probe.psi.size()); ++a)
      if (!contains(members, a) && !contains(pruned, a)) lc.add_action(name(a));
    emit(lc, "macro", "the successful probe episodes converge " + names(members) +
                          ", each while running itself, in this order; the sequence of them replaces them (a composition: no learning cost)" +
                          (pruned.empty() ? std::string() : ", and the pruned actions (" + names(pruned) + ") are left out"));
  }

  // The actions chosen, in at least half of the successful episodes that reach both, from the
  // first CONV of action `from` (-1: the start) to the first CONV of action `to` (-1: the end),
  // without the actions `pruned`, in Psi's order.
  std::vector<int> used_between(int from, int to, const std::vector<int>& pruned) const {
    std::vector<int> count(probe.psi.size(), 0);
    int episodes = 0;
    for (const auto& e : probe.successes) {
      const int lo = from < 0 ? 0 : e.first_conv[size_t(from)];
      const int hi = to < 0 ? int(e.path.size()) : e.first_conv[size_t(to)];
      if (lo < 0 || hi < 0) continue;
      ++episodes;
      std::vector<bool> seen(probe.psi.size(), false);
      for (int d = lo; d < hi && d < int(e.path.size()); ++d) seen[size_t(e.path[size_t(d)])] = true;
      for (size_t a = 0; a < seen.size(); ++a) count[a] += seen[a];
    }
    std::vector<int> used;
    for (int a = 0; a < int(count.size()); ++a)
      if (episodes > 0 && 2 * count[size_t(a)] >= episodes && !contains(pruned, a)) used.push_back(a);
    return used;
  }

  // Learned subgoal stages reaching subgoals `chain` (indices into s.subgoals, in order), each with
  // the actions the successful episodes choose on the way there (and the subgoal itself), then the
  // task with the last skill and the actions chosen after it (or all of Psi: `add`).
  void subgoal_stages(const std::vector<size_t>& chain, bool add, const std::vector<int>& pruned) {
    LuaCandidate lc{task, {}, {}, {}, {}};
    std::vector<std::string> carried;  // the previous subgoal's skill
    int from = -1;
    std::string why;
    for (size_t j : chain) {
      const Subgoal& g = s.subgoals[j];
      SubStage sub{name(g.action), carried, "Phi_to_" + ident(name(g.action)), {}};
      if (!carried.empty()) sub.names.push_back(lc.subs.back().skill);
      std::vector<int> acts = used_between(from, g.action, pruned);
      if (!contains(acts, g.action)) acts.push_back(g.action);
      for (int a : acts) sub.actions.push_back(LuaCandidate::act(name(a))), sub.names.push_back(name(a));
      carried = {ident(sub.skill)};
      lc.subs.push_back(sub);
      from = g.action;
      why += (why.empty() ? "" : "; ") + subgoal_why(g);
    }
    lc.final_actions.push_back(carried[0]), lc.final_names.push_back(lc.subs.back().skill);
    std::vector<int> after = add ? std::vector<int>{} : used_between(from, -1, pruned);
    if (!add && s.final_achiever >= 0 && !contains(after, s.final_achiever)) after.push_back(s.final_achiever);
    for (int a = 0; a < int(probe.psi.size()); ++a)
      if (add || contains(after, a)) lc.add_action(name(a));
    emit(lc, chain.size() > 1 ? "chain" : "subgoal",
         why + (add ? "; the task keeps all of Psi beside the skill"
                    : "; the task keeps the skill and the actions chosen after it in half the successful episodes"));
  }
};

}  // namespace

std::vector<CandidateSpec> generate_candidates(const TaskRef& task, const ProbeStats& probe,
                                               const ProbeSummary& s, double prune_below) {
  Generator gen{task, probe, s, {}, {}};
  const int n = int(probe.psi.size());
  {
    LuaCandidate lc{task, {}, {}, {}, {}};
    for (const auto& a : probe.psi) lc.add_action(a);
    gen.emit(lc, "base", "the starting context as given: the baseline a proposal must beat");
  }
  // The actions running under prune_below of the successful time, but never one the task's goal or
  // a subgoal was reached under: a goal's last step can be short, and a candidate without it could
  // never succeed.
  std::vector<int> achievers{s.final_achiever};
  for (const Subgoal& g : s.subgoals) achievers.push_back(g.achiever);
  std::vector<int> pruned;
  for (int a = 0; a < n && !probe.successes.empty(); ++a)
    if (s.tick_share[size_t(a)] < prune_below && !contains(achievers, a)) pruned.push_back(a);
  const std::vector<int> path = subgoal_path(s);
  if (path.size() >= 2) gen.macro(path, pruned);
  const size_t k = s.subgoals.size();
  if (k >= 1) gen.subgoal_stages({k - 1}, false, pruned);
  if (path.size() >= 2) gen.macro(path, {});
  if (k >= 2) gen.subgoal_stages({0, k - 1}, false, pruned);
  for (size_t j = k >= 1 ? k - 1 : 0; j-- > 0;) gen.subgoal_stages({j}, false, pruned);
  if (!pruned.empty() && int(pruned.size()) < n) {
    LuaCandidate lc{task, {}, {}, {}, {}};
    std::string list;
    for (int a = 0; a < n; ++a) {
      if (!contains(pruned, a)) lc.add_action(probe.psi[size_t(a)]);
      else list += (list.empty() ? "" : ", ") + probe.psi[size_t(a)] + " " + percent(s.tick_share[size_t(a)]);
    }
    gen.emit(lc, "pruned", "pruned the actions that ran under " + percent(prune_below) +
                               " of the successful probe episodes' control ticks: " + list);
  }
  for (size_t i = 0; path.size() >= 3 && i + 1 < path.size(); ++i) gen.macro({path[i], path[i + 1]}, pruned);
  if (k >= 1) gen.subgoal_stages({k - 1}, true, pruned);
  return gen.out;
}

}  // namespace roger::propose_detail
