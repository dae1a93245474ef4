#!/usr/bin/env python3
"""dqn.py: a deep Q-network learns a stage of a curriculum through the Python module, and is timed
against the engine's tabular Q-learner under the same protocol (docs/results.md, "Deep RL").

    PYTHONPATH=build/python python3 scripts/dqn.py --contexts B2 DC6 --seeds 1-10 --out out/dqn

Needs PyTorch (Debian's python3-torch, CPU). For each context and seed it runs, in the same worlds:

- the DQN: one decision of the semi-MDP per step (the controller-state vector one-hot in, one value
  per action out), epsilon-greedy with the stage's schedule (linear over its budget of episodes),
  training episode e in the world of roger.mix(seed, e + 1) as `roger train` does;
- `roger train` of the same stage, context and seed (the tabular learner).

The checkpoint protocol is roger train's (docs/curricula.md, Checkpoints): every `every` training
episodes the greedy policy runs on the held-out seeds; time-to-threshold is the simulated training
time at the first checkpoint from which the success rate stays at or above the threshold to the
end; training stops after `stop_after` consecutive passing checkpoints of one greedy policy (the
greedy action of every state met in training) or at the budget (then censored). DC6's learned skill
Phi_SG is the greedy policy of `roger train --stage SG --context DC2` with the same seed, for both
learners, as in scripts/paper.lua (Table II counts T's time alone).

Writes <out>/<context>-<seed>.json per trial (resumable: a trial with its file is not rerun) and
<out>/table.md.
"""
import argparse
import json
import os
import random
import statistics
import subprocess
import sys
import time

import numpy as np

try:
    import torch
    from torch import nn
except ImportError:
    sys.exit("dqn.py needs PyTorch: apt-get install python3-torch (or ROGER_TORCH=1 bash .ci/install)")

import roger

CURRICULUM = "curricula/paper.lua"


class QNet(nn.Module):
    def __init__(self, actions, hidden=64):
        super().__init__()
        self.actions = actions
        self.net = nn.Sequential(nn.Linear(3 * actions, hidden), nn.ReLU(), nn.Linear(hidden, hidden), nn.ReLU(),
                                 nn.Linear(hidden, actions))

    def forward(self, x):
        return self.net(x)


def one_hot(obs):
    """The state vector (0 NOREF, 1 !CONV, 2 CONV per action) as 3 bits per action."""
    x = np.zeros((len(obs), 3), dtype=np.float32)
    x[np.arange(len(obs)), obs] = 1.0
    return x.reshape(-1)


class Agent:
    """DQN over decisions: replay, a target network, Huber loss, rewards scaled by 1/100."""

    def __init__(self, actions, discount, seed, lr=1e-3, batch=64, buffer=20000, target_every=200):
        torch.manual_seed(seed)
        self.rng = random.Random(seed)
        self.q = QNet(actions)
        self.target = QNet(actions)
        self.target.load_state_dict(self.q.state_dict())
        self.opt = torch.optim.Adam(self.q.parameters(), lr=lr)
        self.discount, self.batch, self.buffer, self.target_every = discount, batch, buffer, target_every
        self.memory, self.updates = [], 0
        self.actions = actions
        self.greedy_cache = {}

    def greedy(self, obs):
        key = tuple(int(v) for v in obs)
        if key not in self.greedy_cache:
            with torch.no_grad():
                self.greedy_cache[key] = int(torch.argmax(self.q(torch.from_numpy(one_hot(obs)))).item())
        return self.greedy_cache[key]

    def choose(self, obs, epsilon):
        if epsilon > 0 and self.rng.random() < epsilon:
            return self.rng.randrange(self.actions)
        return self.greedy(obs)

    def remember(self, s, a, r, s2, done):
        if len(self.memory) >= self.buffer:
            self.memory[self.rng.randrange(self.buffer)] = (s, a, r, s2, done)
        else:
            self.memory.append((s, a, r, s2, done))

    def learn(self):
        if len(self.memory) < self.batch:
            return
        s, a, r, s2, d = zip(*self.rng.sample(self.memory, self.batch))
        s = torch.from_numpy(np.stack([one_hot(x) for x in s]))
        s2 = torch.from_numpy(np.stack([one_hot(x) for x in s2]))
        a = torch.tensor(a)
        r = torch.tensor(r, dtype=torch.float32) / 100.0
        d = torch.tensor(d, dtype=torch.float32)
        with torch.no_grad():
            target = r + self.discount * (1.0 - d) * self.target(s2).max(1).values
        q = self.q(s).gather(1, a.unsqueeze(1)).squeeze(1)
        loss = nn.functional.smooth_l1_loss(q, target)
        self.opt.zero_grad()
        loss.backward()
        self.opt.step()
        self.greedy_cache.clear()
        self.updates += 1
        if self.updates % self.target_every == 0:
            self.target.load_state_dict(self.q.state_dict())


def run_episode(env, seed, act, on_step=None):
    """One episode; returns (success, sim seconds, the states where it decided and the actions)."""
    obs, _ = env.reset(seed=seed)
    decisions = []
    while True:
        a = act(obs)
        decisions.append((tuple(int(v) for v in obs), a))
        obs2, reward, terminated, truncated, info = env.step(a)
        if on_step:  # no bootstrap beyond a terminal state (the stage's time-out is one); a truncation bootstraps
            on_step(obs, a, reward, obs2, terminated)
        obs = obs2
        if terminated or truncated:
            return info.get("success", False), info["sim_seconds"], decisions


class EvalCache:
    """As roger train's: a greedy episode is a function of its world and of the greedy actions at
    the states it decides in, so an episode whose every decision state still gets the same greedy
    action would run again the same and is reused."""

    def __init__(self):
        self.by_seed = {}

    def evaluate(self, env, agent, first_seed, episodes):
        successes = 0
        for i in range(episodes):
            seed = first_seed + i
            kept = self.by_seed.get(seed)
            if kept is None or any(agent.greedy(np.array(s)) != a for s, a in kept[1]):
                success, _, decisions = run_episode(env, seed, agent.greedy)
                kept = self.by_seed[seed] = (success, decisions)
            successes += kept[0]
        return successes / episodes


def train_dqn(env, seed):
    info = env.stage_info
    cp, learner = info["checkpoints"], info["learner"]
    budget = info["budget_episodes"]
    agent = Agent(len(env.actions), learner["discount"], seed)
    cache = EvalCache()
    spent_sim = 0.0
    seen_states = set()
    curve, passing, settled, signature_before = [], 0, 0, None
    t0 = time.perf_counter()

    def on_step(s, a, r, s2, done):
        seen_states.add(tuple(int(v) for v in s))
        agent.remember(s, a, r, s2, done)
        agent.learn()

    for e in range(budget):
        eps = epsilon(learner, e, budget)
        _, sim_s, _ = run_episode(env, roger.mix(seed, e + 1), lambda o: agent.choose(o, eps), on_step)
        spent_sim += sim_s
        if (e + 1) % cp["every"] == 0 or e + 1 == budget:
            rate = cache.evaluate(env, agent, cp["seeds"], cp["episodes"])
            curve.append({"episodes": e + 1, "sim_s": spent_sim, "success_rate": rate})
            passed = rate >= cp["threshold"]
            passing = passing + 1 if passed else 0
            signature = {s: agent.greedy(np.array(s)) for s in sorted(seen_states)}
            changed = signature != signature_before
            settled = 0 if not passed else 1 if changed and cp["settle"] else settled + 1
            signature_before = signature
            if cp["stop_after"] > 0 and settled >= cp["stop_after"] and e + 1 < budget:
                break
    reached = passing > 0
    to_threshold = curve[len(curve) - passing]["sim_s"] if reached else spent_sim
    final = cache.evaluate(env, agent, cp["seeds"], cp["final"])
    return {"learner": "dqn", "reached": reached, "time_to_threshold_s": to_threshold, "train_sim_s": spent_sim,
            "train_episodes": curve[-1]["episodes"], "success_rate": final, "wall_s": time.perf_counter() - t0,
            "curve": curve}


def epsilon(learner, spent, budget):
    """roger's ExplorationSchedule over episodes: exact at both ends, linear between."""
    if spent <= 0:
        return learner["epsilon_start"]
    if spent >= budget:
        return learner["epsilon_end"]
    return learner["epsilon_start"] + (learner["epsilon_end"] - learner["epsilon_start"]) * (spent / budget)


def roger_train(roger_bin, context, seed, out, skills=()):
    cmd = [roger_bin, "train", CURRICULUM, "--stage", "T" if context != "DC2" else "SG", "--context", context,
           "--seed", str(seed), "--out", out, "--json"]
    for k, v in skills:
        cmd += ["--skill", f"{k}={v}"]
    t0 = time.perf_counter()
    r = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.strip().splitlines()[-1])
    r["wall_s"] = time.perf_counter() - t0
    return r


def trial(a, context, seed):
    path = os.path.join(a.out, f"{context}-{seed}.json")
    if os.path.exists(path):
        with open(path) as f:
            return json.load(f)
    skills = {}
    if context in ("DC3", "DC4", "DC5", "DC6"):
        sg = os.path.join(a.out, "policies", f"SG-DC2-{seed}")
        if not os.path.exists(os.path.join(sg, "policy.json")):
            roger_train(a.roger, "DC2", seed, sg)
        skills = {"Phi_SG": os.path.join(sg, "policy.json")}
    tab = roger_train(a.roger, context, seed, os.path.join(a.out, "policies", f"T-{context}-{seed}"), skills.items())
    env = roger.make(CURRICULUM, "T", context, skills=skills)
    dqn = train_dqn(env, seed)
    result = {"context": context, "seed": seed, "dqn": dqn,
              "tabular": {k: tab[k] for k in ("reached", "time_to_threshold_s", "train_sim_s", "train_episodes",
                                               "success_rate", "wall_s")}}
    os.makedirs(a.out, exist_ok=True)
    with open(path + ".tmp", "w") as f:
        json.dump(result, f)
    os.replace(path + ".tmp", path)
    return result


def minsec(s):
    if s >= 3600 * 100:
        return "-"
    t = int(s + 0.5)  # whole seconds first, as the engine's tables round (59.7 s is 1:00, not 0:60)
    return f"{t // 60}:{t % 60:02d}"


def first_pass(curve, threshold):
    """The simulated training time of the first checkpoint at or above the threshold (None: none)."""
    return next((c["sim_s"] for c in curve if c["success_rate"] >= threshold), None)


def tabular_curve(out, context, seed):
    """roger train's curve.csv of a trial, as dicts."""
    with open(os.path.join(out, "policies", f"T-{context}-{seed}", "curve.csv")) as f:
        rows = [line.strip().split(",") for line in f][1:]
    return [{"sim_s": float(r[1]), "success_rate": float(r[4])} for r in rows]


def table(results, contexts, out, threshold=0.9):
    lines = ["| Context | Learner | Trials | Reached | Mean time-to-threshold (min:sec, simulated) | Median | "
             "Median first pass | Final success | Wall s per trial |", "|---|---|---|---|---|---|---|---|---|"]
    for c in contexts:
        rs = [r for r in results if r["context"] == c]
        for learner in ("tabular", "dqn"):
            xs = [r[learner] for r in rs]
            if not xs:
                continue
            times = [x["time_to_threshold_s"] for x in xs]
            curves = [x["curve"] if learner == "dqn" else tabular_curve(out, c, r["seed"]) for x, r in zip(xs, rs)]
            firsts = [first_pass(k, threshold) for k in curves]
            first = minsec(statistics.median(firsts)) if None not in firsts else "-"
            # A censored trial counts its whole training time, the most any trial has: the mean is
            # then a lower bound, and the median too once half the trials are censored.
            censored = sum(not x["reached"] for x in xs)
            mean = ("\u2265 " if censored else "") + minsec(statistics.mean(times))
            median = ("\u2265 " if 2 * censored >= len(xs) else "") + minsec(statistics.median(times))
            lines.append(f"| {c} | {'Q-table (roger train)' if learner == 'tabular' else 'DQN (scripts/dqn.py)'} | "
                         f"{len(xs)} | {sum(x['reached'] for x in xs)}/{len(xs)} | {mean} | "
                         f"{median} | {first} | "
                         f"{100 * statistics.mean(x['success_rate'] for x in xs):.1f}% | "
                         f"{statistics.mean(x['wall_s'] for x in xs):.1f} |")
    return ("\n".join(lines) + "\n\nA trial that did not reach the threshold counts its whole training time "
            "(censored; a mean over one, and a median over half or more, is a lower bound: \u2265). First pass: the first checkpoint at or above the threshold, whether or not the rate "
            "stayed there.\n")


def parse_seeds(text):
    if "-" in text:
        lo, hi = text.split("-")
        return list(range(int(lo), int(hi) + 1))
    return [int(s) for s in text.split(",")]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--contexts", nargs="+", default=["B2", "DC6"])
    ap.add_argument("--seeds", default="1-10", help="a range 1-10 or a list 1,2,3")
    ap.add_argument("--out", default="out/dqn")
    ap.add_argument("--roger", default="build/engine/roger")
    a = ap.parse_args()
    torch.set_num_threads(1)
    os.makedirs(a.out, exist_ok=True)
    results = []
    for context in a.contexts:
        for seed in parse_seeds(a.seeds):
            r = trial(a, context, seed)
            results.append(r)
            d, t = r["dqn"], r["tabular"]
            print(f"{context} seed {seed}: DQN {'reached' if d['reached'] else 'NOT reached'} in "
                  f"{minsec(d['time_to_threshold_s'])} ({d['wall_s']:.0f} wall s), tabular "
                  f"{'reached' if t['reached'] else 'NOT reached'} in {minsec(t['time_to_threshold_s'])}", flush=True)
    text = table(results, a.contexts, a.out)
    with open(os.path.join(a.out, "table.md"), "w") as f:
        f.write(text)
    print("\n" + text)


if __name__ == "__main__":
    sys.exit(main())
