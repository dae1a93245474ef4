#!/usr/bin/env python3
"""bench_python.py: what the Python module costs and gains (docs/python.md, Performance).

    PYTHONPATH=build/python python3 scripts/bench_python.py [--roger PATH] [--rounds 5]

1. Batched stepping: make_vec with N worlds stepped by 1 thread and by 2 threads, and the same N
   worlds as separate environments stepped one after the other from Python; steps (decisions) per
   wall second and simulated seconds per wall second, the same seeded random actions in all three.
2. Overhead over the engine alone: `roger eval` of a policy (C++ only) against the Python loop
   `env.step(policy.act(obs))` over the same episodes, which runs the same ticks.

Each measurement is paired: the variants run one after the other within a round, rounds repeat,
and the ratio is taken within each round, so a shared machine's load moves both sides alike. The
median ratio is reported, with the load average before and after. The roger program: --roger, else
$ROGER, else the source tree's build/engine/roger, else roger on PATH (a missing one stops the
script with one line, before anything is measured).
"""
import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import roger

sys.dont_write_bytecode = True  # results_common, imported below, leaves no __pycache__ in scripts/
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # its folder: also when loaded by path or run with -P
from results_common import find_roger  # noqa: E402

NAME = "bench_python.py"  # in the messages of results_common's functions

CURRICULUM = "curricula/paper.lua"


def vec_run(num_envs, threads, steps, seed):
    vec = roger.make_vec(CURRICULUM, "T", "B2", num_envs=num_envs, threads=threads)
    rng = np.random.default_rng(seed)
    vec.reset(seed=seed)
    actions = [rng.integers(0, len(vec.actions), size=num_envs) for _ in range(steps)]
    t0, c0 = time.perf_counter(), time.process_time()
    for a in actions:
        vec.step(a)
    return time.perf_counter() - t0, steps * num_envs, time.process_time() - c0


def separate_run(num_envs, steps, seed):
    envs = [roger.make(CURRICULUM, "T", "B2") for _ in range(num_envs)]
    rng = np.random.default_rng(seed)
    for i, e in enumerate(envs):
        e.reset(seed=seed + i)
    started, ended = [1] * num_envs, [False] * num_envs
    actions = [rng.integers(0, len(envs[0].actions), size=num_envs) for _ in range(steps)]
    bound_wall = 0.0
    t0 = time.perf_counter()
    for a in actions:
        job_times = []
        for i, e in enumerate(envs):
            tj = time.perf_counter()
            if ended[i]:  # make_vec's NEXT_STEP autoreset: the step after an end begins the next episode
                e.reset(seed=seed + i + started[i] * num_envs)
                started[i] += 1
                ended[i] = False
            else:
                _, _, term, trunc, _ = e.step(int(a[i]))
                ended[i] = term or trunc
            job_times.append(time.perf_counter() - tj)
        bound_wall += two_thread_wall(job_times)
    wall = time.perf_counter() - t0
    return wall, steps * num_envs, bound_wall


def two_thread_wall(job_times):
    """How long one batched step of these jobs takes on two threads that take the next job in
    index order as each becomes free (VecEnvironment's hand-out), with no waiting for a core: the
    step's wall time on an idle 2-core machine, what the batch's balance allows."""
    free = [0.0, 0.0]
    for t in job_times:
        k = 0 if free[0] <= free[1] else 1
        free[k] += t
    return max(free)


def python_eval(policy_file, episodes, seed):
    t0, c0 = time.perf_counter(), time.process_time()
    env = roger.make(CURRICULUM, "T", "B2")
    policy = roger.load_policy(policy_file)
    decisions = 0
    for i in range(episodes):
        obs, _ = env.reset(seed=seed + i)
        done = False
        while not done:
            obs, _, term, trunc, info = env.step(policy.act(obs))
            done = term or trunc
        decisions += info["decisions"]
    return time.perf_counter() - t0, decisions, time.process_time() - c0


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


class TimedEngine:
    """Wraps an Env's engine object, adding up the wall time spent inside every call into it (the
    C++ engine's work), so that the rest of the loop's time is what Python adds. Every method and
    property is timed, not a chosen few: Env.reset builds the world through reset_task, and a
    wrapper that timed reset and step alone counted that world building as Python's."""

    def __init__(self, inner):
        self.inner, self.seconds = inner, 0.0

    def __getattr__(self, name):
        t0 = time.perf_counter()
        value = getattr(self.inner, name)  # a property (sim_seconds, running...) is read in the engine
        self.seconds += time.perf_counter() - t0
        if not callable(value):
            return value

        def timed(*args, **kwargs):
            t0 = time.perf_counter()
            try:
                return value(*args, **kwargs)
            finally:
                self.seconds += time.perf_counter() - t0
        return timed


def python_share(policy_file, episodes, seed):
    """In one process: the loop's wall time over the time inside the engine's calls, minus 1."""
    env = roger.make(CURRICULUM, "T", "B2")
    policy = roger.load_policy(policy_file)
    env._env = engine = TimedEngine(env._env)
    t0 = time.perf_counter()
    for i in range(episodes):
        obs, _ = env.reset(seed=seed + i)
        done = False
        while not done:
            obs, _, term, trunc, _ = env.step(policy.act(obs))
            done = term or trunc
    return (time.perf_counter() - t0) / engine.seconds - 1.0


def cpp_eval(roger_bin, policy_file, episodes, seed):
    t0, c0 = time.perf_counter(), children_cpu()
    out = subprocess.run([roger_bin, "eval", CURRICULUM, "--policy", policy_file, "--episodes", str(episodes),
                          "--seed", str(seed), "--json"], check=True, capture_output=True, text=True).stdout
    return time.perf_counter() - t0, json.loads(out.strip().splitlines()[-1]), children_cpu() - c0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--roger", help="the roger program (default: $ROGER, else the source tree's "
                    "build/engine/roger, else roger on PATH)")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--envs", type=int, default=32)
    ap.add_argument("--steps", type=int, default=100, help="vec steps per round")
    ap.add_argument("--episodes", type=int, default=400, help="evaluation episodes per round")
    ap.add_argument("--policy", help="a T/B2 policy.json (default: roger train --seed 1 into a temporary folder)")
    a = ap.parse_args()
    # Found by a probe: the installed copy looked for build/engine/roger in the current folder and
    # died with a traceback after half the measurements.
    a.roger = find_roger(NAME, a.roger)
    load0 = os.getloadavg()
    policy = a.policy
    if not policy:
        out = tempfile.mkdtemp(prefix="bench-python-")
        subprocess.run([a.roger, "train", CURRICULUM, "--stage", "T", "--context", "B2", "--seed", "1", "--out", out],
                       check=True, capture_output=True)
        policy = os.path.join(out, "policy.json")

    speedups, vs_separate, rates = [], [], {1: [], 2: [], "separate": []}
    cpu_ratio, overheads, cpu_overheads, per_step, shares, bounds = [], [], [], [], [], []
    for r in range(a.rounds):
        seed = 10 * r + 1
        w1, n, c1 = vec_run(a.envs, 1, a.steps, seed)
        w2, _, c2 = vec_run(a.envs, 2, a.steps, seed)
        ws, _, bound = separate_run(a.envs, a.steps, seed)
        bounds.append(ws / bound)
        rates[1].append(n / w1)
        rates[2].append(n / w2)
        rates["separate"].append(n / ws)
        speedups.append(w1 / w2)
        vs_separate.append(ws / w2)
        cpu_ratio.append(c2 / c1)
        wc, summary, cc = cpp_eval(a.roger, policy, a.episodes, 1000000)
        wp, decisions, cp = python_eval(policy, a.episodes, 1000000)
        overheads.append(wp / wc - 1.0)
        cpu_overheads.append(cp / cc - 1.0)
        per_step.append((cp - cc) / decisions * 1e6)
        shares.append(python_share(policy, a.episodes, 1000000))
        print(f"round {r + 1}: vec 1 thread {n / w1:7.1f} steps/s, 2 threads {n / w2:7.1f} steps/s "
              f"(x{w1 / w2:.2f}; CPU x{c2 / c1:.2f}), separate envs {n / ws:7.1f} steps/s; eval C++ {wc:.2f} s "
              f"({cc:.2f} CPU s), Python {wp:.2f} s ({cp:.2f} CPU s): {100 * (wp / wc - 1):+.1f}% wall, "
              f"{100 * (cp / cc - 1):+.1f}% CPU", flush=True)
    load1 = os.getloadavg()
    med = statistics.median
    print(f"\nmake_vec, {a.envs} worlds of T/B2, random actions, {a.steps} steps x {a.rounds} rounds:")
    print(f"  1 thread            {med(rates[1]):8.1f} steps/s")
    print(f"  2 threads           {med(rates[2]):8.1f} steps/s   "
          f"speed-up x{med(speedups):.2f} (median of paired rounds)")
    print(f"  separate Envs       {med(rates['separate']):8.1f} steps/s   2-thread make_vec is x{med(vs_separate):.2f}")
    print(f"  CPU time per step, 2 threads over 1: x{med(cpu_ratio):.2f} (the work the threads add)")
    print(f"  the batch's balance allows x{med(bounds):.2f} on an idle 2-core machine (each world's step timed "
          f"alone, the two threads' hand-out simulated)")
    print(f"Python loop over roger eval, {a.episodes} episodes of T/B2 from seed 1000000: overhead "
          f"{100 * med(overheads):+.1f}% of wall time, {100 * med(cpu_overheads):+.1f}% of CPU time "
          f"({med(per_step):.1f} CPU us per step; medians of the rounds)")
    print(f"  in one process, the loop's time outside the engine's calls: {100 * med(shares):+.1f}% of the time "
          f"inside them (rounds {', '.join(f'{100 * x:+.1f}%' for x in shares)})")
    print(f"load average before {load0[0]:.2f}, after {load1[0]:.2f} on {os.cpu_count()} cores")


if __name__ == "__main__":
    sys.exit(main())
