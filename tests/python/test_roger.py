#!/usr/bin/env python3
"""test_roger.py: the Python module roger (CTest label `python`; docs/python.md).

    ROGER=build/engine/roger PYTHONPATH=build/python python3 tests/python/test_roger.py [-k NAME]

Run from the repository root. Needs numpy and the built module, never torch or gymnasium. Each
class is one CTest test. Policies come from short `roger train` runs, made once per process in
ROGER_TEST_WORK (emptied first) or a temporary folder.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

import roger

ROGER = os.environ.get("ROGER", "build/engine/roger")
WORK = os.environ.get("ROGER_TEST_WORK") or tempfile.mkdtemp(prefix="roger-python-")
if os.environ.get("ROGER_TEST_WORK"):  # every run trains its policies afresh, with this build
    shutil.rmtree(WORK, ignore_errors=True)
    os.makedirs(WORK)
EXAMPLE = "docs/examples/curriculum_example.lua"
BAD_REWARD = "tests/python/fixtures/bad_reward.lua"
PAPER = "curricula/paper.lua"
FIRST_SEED = 1000000


def train(curriculum, stage, context, seed, name, skills=()):
    """policy.json of a `roger train` run (made once)."""
    out = os.path.join(WORK, name)
    policy = os.path.join(out, "policy.json")
    if not os.path.exists(policy):
        cmd = [ROGER, "train", curriculum, "--stage", stage, "--context", context, "--seed", str(seed), "--out", out]
        for k, v in skills:
            cmd += ["--skill", f"{k}={v}"]
        subprocess.run(cmd, check=True, capture_output=True)
    return policy


def roger_eval(curriculum, policy, episodes, seed):
    out = subprocess.run([ROGER, "eval", curriculum, "--policy", policy, "--episodes", str(episodes),
                          "--seed", str(seed), "--json"], check=True, capture_output=True, text=True).stdout
    return json.loads(out.strip().splitlines()[-1])


def python_eval(env, policy, episodes, seed, details=None):
    """The Python loop of docs/python.md: successes and per-episode returns. `details`, if given,
    receives the mean simulated time and each action's share of the decisions, as roger eval
    computes them."""
    successes, returns, time, counts = 0, [], 0.0, [0] * len(env.actions)
    for i in range(episodes):
        obs, info = env.reset(seed=seed + i)
        total, done = 0.0, False
        while not done:
            a = policy.act(obs)
            counts[a] += 1
            obs, reward, terminated, truncated, info = env.step(a)
            total += reward
            done = terminated or truncated
        successes += int(terminated)
        returns.append(total)
        time += info["sim_seconds"]
        assert total == info["episode_reward"], (total, info["episode_reward"])
    if details is not None:
        details["time_mean"] = time / episodes
        details["usage"] = {name: c / sum(counts) for name, c in zip(env.actions, counts)}
    return successes, returns


def summary(returns):
    """roger eval's mean and population std of a policy file, computed in its order (two passes)."""
    mean = 0.0
    for r in returns:
        mean += r
    mean /= len(returns)
    var = 0.0
    for r in returns:
        var += (r - mean) * (r - mean)
    return mean, (var / len(returns)) ** 0.5


class EvalMatches(unittest.TestCase):
    """load_policy(...).act over 20 episodes from seed 1000000 = roger eval, exactly."""

    def check(self, curriculum, policy_file, stage, context, skills=None):
        expected = roger_eval(curriculum, policy_file, 20, FIRST_SEED)
        env = roger.make(curriculum, stage=stage, context=context, skills=skills)
        policy = roger.load_policy(policy_file)
        self.assertEqual(policy.actions, env.actions)
        details = {}
        successes, returns = python_eval(env, policy, 20, FIRST_SEED, details)
        self.assertEqual(successes, expected["successes"])
        mean, std = summary(returns)
        self.assertEqual(mean, expected["reward_mean"])
        self.assertEqual(std, expected["reward_std"])
        # The same episodes, not only the same outcomes: their simulated times and decisions too.
        self.assertEqual(details["time_mean"], expected["time_mean"])
        self.assertEqual(details["usage"], expected["usage"])
        return expected

    def test_lua_reward_stage(self):
        # A stage with a Lua reward (-1 per decision): rewards other than +-100 must match too.
        self.check(EXAMPLE, train(EXAMPLE, "Look", "Gaze", 3, "look"), "Look", "Gaze")

    def test_paper_transport_b2(self):
        r = self.check(PAPER, train(PAPER, "T", "B2", 1, "t-b2"), "T", "B2")
        self.assertGreater(r["successes"], 0)  # a policy that does something: the match is not trivial

    def test_paper_transport_with_learned_skill(self):
        sg = train(PAPER, "SG", "DC2", 1, "sg-dc2")
        t = train(PAPER, "T", "DC6", 1, "t-dc6", skills=[("Phi_SG", sg)])
        self.check(PAPER, t, "T", "DC6", skills={"Phi_SG": sg})


class VecDeterminism(unittest.TestCase):
    """make_vec: the same episodes with 1 and 2 threads, and the same as single environments."""

    N, STEPS = 4, 120

    def run_vec(self, threads):
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=self.N, threads=threads)
        self.assertEqual(vec.threads, threads)
        rng = np.random.default_rng(5)
        obs, info = vec.reset(seed=100)
        trace = [obs.copy(), info["seed"].copy()]
        for _ in range(self.STEPS):
            actions = rng.integers(0, len(vec.actions), size=self.N)
            obs, rew, term, trunc, info = vec.step(actions)
            trace += [actions, obs.copy(), rew.copy(), term.copy(), trunc.copy(), info["episode_seed"].copy(),
                      info["episode_sim_s"].copy(), info["episode_ticks"].copy(), info["final_observation"].copy()]
        return trace

    def test_one_and_two_threads(self):
        one, two = self.run_vec(1), self.run_vec(2)
        self.assertEqual(len(one), len(two))
        for a, b in zip(one, two):
            np.testing.assert_array_equal(a, b)
        ended = sum(int(np.count_nonzero(t)) for t in one[4::9]) + sum(int(np.count_nonzero(t)) for t in one[5::9])
        self.assertGreater(ended, self.N)  # auto-reset was exercised

    def test_same_as_single_environments(self):
        trace = self.run_vec(2)
        env = roger.make(EXAMPLE, "Look", "Gaze")
        for i in range(self.N):
            seed = 100 + i
            obs, _ = env.reset(seed=seed)
            np.testing.assert_array_equal(obs, trace[0][i])
            for k in range(self.STEPS):
                actions, vobs, rew, term, trunc, ep_seed, sim_s, ticks, final = trace[2 + 9 * k: 11 + 9 * k]
                obs, reward, terminated, truncated, info = env.step(int(actions[i]))
                self.assertEqual(reward, rew[i])
                self.assertEqual(terminated, bool(term[i]))
                self.assertEqual(truncated, bool(trunc[i]))
                if terminated or truncated:
                    self.assertEqual(ep_seed[i], seed)
                    self.assertEqual(sim_s[i], info["sim_seconds"])
                    self.assertEqual(ticks[i], info["ticks"])
                    np.testing.assert_array_equal(final[i], obs)
                    seed += self.N
                    obs, _ = env.reset(seed=seed)
                np.testing.assert_array_equal(obs, vobs[i])


class Interface(unittest.TestCase):
    """Spaces, info, the per-tick mode."""

    def test_decision_mode(self):
        env = roger.make(EXAMPLE, stage="Look", context="Gaze")
        self.assertEqual(env.actions, ("search", "phi0"))
        self.assertEqual(env.action_space.n, 2)
        self.assertEqual(list(env.observation_space.nvec), [3, 3])
        obs, info = env.reset(seed=7)
        self.assertTrue(env.observation_space.contains(obs))
        self.assertEqual(set(info["state"]), {"search", "phi0"})
        self.assertEqual(info["ticks"], 0)
        obs, reward, terminated, truncated, info = env.step(0)
        self.assertGreater(info["ticks"], 0)
        self.assertAlmostEqual(info["sim_seconds"], info["ticks"] * env.stage_info["tick_seconds"])
        self.assertIn(info["state"]["search"], roger.GAMMA_NAMES)
        # The example's learner discounts once per decision, as roger train does with it.
        self.assertEqual(env.stage_info["learner"]["discount_seconds"], 0.0)
        self.assertEqual(env.stage_info["learner"]["discount"], 0.95)
        self.assertFalse(env.stage_info["learner"]["unconverged_first"])
        self.assertEqual(env.stage_info["time_limit"], 4.0)
        self.assertEqual(env.stage_info["time_per_object"], 0.0)

    def test_time_limit_per_object(self):
        # The sorting stages time out after 30 s per object of the episode's world.
        env = roger.make("curricula/sorting.lua", stage="Hand2", context="Scripted")
        self.assertEqual(env.stage_info["time_limit"], 0.0)
        self.assertEqual(env.stage_info["time_per_object"], 30.0)
        # ...and their learner chooses among the types still on their way first.
        self.assertTrue(env.stage_info["learner"]["unconverged_first"])

    def test_tick_mode(self):
        env = roger.make(EXAMPLE, stage="Look", context="Gaze", mode="tick")
        obs, info = env.reset(seed=7)
        self.assertEqual(obs["images"].shape, (2, 128, 3))
        self.assertEqual(obs["touch"].shape, (3, 5))
        for k in range(5):
            obs, reward, terminated, truncated, info = env.step(0)
            self.assertEqual(info["ticks"], k + 1)  # one control tick per step
        self.assertTrue(env.observation_space.contains(obs))

    def test_gymnasium_base_when_present(self):
        try:
            import gymnasium
        except ImportError:
            self.skipTest("gymnasium is not installed (the module does not need it)")
        self.assertIsInstance(roger.make(EXAMPLE, "Look", "Gaze"), gymnasium.Env)


class BadArguments(unittest.TestCase):
    """Bad input raises a Python exception naming the file and the field, never a crash."""

    def assertRaisesWith(self, exc, texts, fn, *args, **kwargs):
        with self.assertRaises(exc) as cm:
            fn(*args, **kwargs)
        for t in texts:
            self.assertIn(t, str(cm.exception))
        return cm.exception

    def test_unknown_stage_and_context(self):
        self.assertRaisesWith(roger.RogerError, ["Nope", "Look"], roger.make, EXAMPLE, "Nope", "Gaze")
        self.assertRaisesWith(roger.RogerError, ["Nope", "Gaze"], roger.make, EXAMPLE, "Look", "Nope")
        self.assertRaisesWith(roger.RogerError, ["no_such_curriculum"], roger.make, "no_such_curriculum", "T", "B2")
        self.assertRaisesWith(roger.RogerError, ["shape"], roger.make, PAPER, "T", "B2", params={"shape": "cube"})

    def test_missing_learned_skill(self):
        self.assertRaisesWith(roger.RogerError, ["Phi_SG", "skills="], roger.make, PAPER, "T", "DC6")

    def test_bad_action(self):
        env = roger.make(EXAMPLE, "Look", "Gaze")
        self.assertRaisesWith(roger.RogerError, ["call reset"], env.step, 0)
        env.reset(seed=1)
        self.assertRaisesWith(roger.RogerError, ["action index 2", "[0, 2)"], env.step, 2)
        self.assertRaisesWith(roger.RogerError, ["action index -1"], env.step, -1)
        self.assertRaisesWith(roger.RogerError, ["integer index"], env.step, 0.5)
        env.step(0)  # the episode still runs after refused actions
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=2, threads=2)
        vec.reset(seed=1)
        self.assertRaisesWith(roger.RogerError, ["action 5 of environment 1"], vec.step, np.array([0, 5]))
        self.assertRaisesWith(roger.RogerError, ["num_envs"], roger.make_vec, EXAMPLE, "Look", "Gaze", num_envs=0)

    def test_malformed_policy_files(self):
        with open(train(EXAMPLE, "Look", "Gaze", 3, "look")) as f:
            good = json.load(f)
        cases = {
            "truncated": ("{\"format\": \"roger-policy\", \"q\": [", ["truncated.json"]),
            "no_q": (json.dumps({k: v for k, v in good.items() if k != "q"}), ["no_q.json", "q"]),
            "short_row": (json.dumps({**good, "q": [r[:1] for r in good["q"]]}), ["short_row.json", "q"]),
            "not_numbers": (json.dumps({**good, "q": [["x", "y"] for _ in good["q"]]}), ["not_numbers.json", "q"]),
            "bad_alpha": (json.dumps({**good, "params": {**good["params"], "alpha": 7}}), ["bad_alpha.json", "alpha"]),
        }
        for name, (text, expected) in cases.items():
            path = os.path.join(WORK, name + ".json")
            with open(path, "w") as f:
                f.write(text)
            with self.subTest(name):
                self.assertRaisesWith(roger.RogerError, expected, roger.load_policy, path)
        self.assertRaisesWith(roger.RogerError, ["missing.json"], roger.load_policy, os.path.join(WORK, "missing.json"))
        policy = roger.load_policy(train(EXAMPLE, "Look", "Gaze", 3, "look"))
        self.assertRaisesWith(roger.RogerError, ["2 actions", "3 values"], policy.act, [0, 1, 2])
        self.assertRaisesWith(roger.RogerError, ["observation[1]", "phi0"], policy.act, [0, 3])

    def test_script_error_in_reward(self):
        env = roger.make(BAD_REWARD, "Look", "Gaze")
        env.reset(seed=1)
        with self.assertRaises(roger.ScriptError) as cm:
            for _ in range(500):
                env.step(0)
        e = cm.exception
        self.assertIn("bad_reward.lua:8", str(e))
        self.assertTrue(e.file.endswith("bad_reward.lua"))
        self.assertEqual(e.line, 8)
        self.assertRaisesWith(roger.RogerError, ["call reset"], env.step, 0)  # the episode is over
        env.reset(seed=2)  # and the environment usable again


if __name__ == "__main__":
    try:
        unittest.main(verbosity=2)
    finally:
        if not os.environ.get("ROGER_TEST_WORK"):
            shutil.rmtree(WORK, ignore_errors=True)
