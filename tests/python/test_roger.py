#!/usr/bin/env python3
"""test_roger.py: the Python module roger (CTest label `python`; docs/python.md).

    ROGER=build/engine/roger PYTHONPATH=build/python python3 tests/python/test_roger.py [-k NAME]

Run from the repository root. Needs numpy and the built module. The classes that need a tool
beyond them (GymnasiumJudges: gymnasium; StableBaselines3: stable-baselines3 and torch) are
skipped where it is missing, and then the run exits 77, which CTest reports as skipped (its
SKIP_RETURN_CODE), never as passed. Under CI (CI=true) a missing tool fails instead, unless
docs/testing.md says CI cannot have it (NOT_IN_CI). Each class is one CTest test. Policies come
from short `roger train` runs, made once per process in ROGER_TEST_WORK (emptied first) or a
temporary folder.
"""
import copy
import importlib
import importlib.util
import json
import os
import pickle
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import textwrap
import threading
import time
import unittest

import numpy as np

import roger

ROGER = os.environ.get("ROGER", "build/engine/roger")
WORK = os.environ.get("ROGER_TEST_WORK")
if __name__ == "__main__":  # not when a spawned process of multiprocessing imports this file
    if WORK:  # every run trains its policies afresh, with this build
        shutil.rmtree(WORK, ignore_errors=True)
        os.makedirs(WORK)
    else:
        WORK = tempfile.mkdtemp(prefix="roger-python-")
EXAMPLE = "docs/examples/curriculum_example.lua"
BAD_REWARD = "tests/python/fixtures/bad_reward.lua"
TIMEOUT_FAULT = "tests/python/fixtures/timeout_fault.lua"
ABSORBING_AT_ONCE = "tests/python/fixtures/absorbing_at_once.lua"
GENERATE_FAILS_ONCE = "tests/python/fixtures/generate_fails_once.lua"
LCAS_LIFT = "tests/python/fixtures/lcas_lift.lua"
PAPER = "curricula/paper.lua"
FIRST_SEED = 1000000

# A test that needs a missing tool is skipped with this exit code (CTest's SKIP_RETURN_CODE, as
# tests/tools/skip.sh); under CI=true it fails instead, unless the tool is one CI cannot have:
# Debian bookworm packages neither of these, and CI installs from Debian's archive alone
# (docs/testing.md, "Tools CI cannot have", which SkipRule holds to this list).
SKIP = 77
NOT_IN_CI = {
    "gymnasium": "Debian bookworm has no gymnasium package",
    "stable_baselines3": "Debian bookworm has no stable-baselines3 package",
}
MISSING_TOOL = "missing tool: "  # how a skip for a missing tool begins its reason


def require(module):
    """`module` imported, or the test skipped for a missing tool (failed under CI=true unless CI
    cannot have it)."""
    try:
        return importlib.import_module(module)
    except ImportError as e:
        if os.environ.get("CI") == "true" and module not in NOT_IN_CI:
            raise AssertionError(f"FAILED (would skip, but CI=true): {module} is not importable ({e}); "
                                 ".ci/install installs what the tests need") from None
        raise unittest.SkipTest(f"{MISSING_TOOL}{module} is not importable ({e})") from None


def train(curriculum, stage, context, seed, name, skills=(), sets=()):
    """policy.json of a `roger train` run (made once)."""
    out = os.path.join(WORK, name)
    policy = os.path.join(out, "policy.json")
    if not os.path.exists(policy):
        cmd = [ROGER, "train", curriculum, "--stage", stage, "--context", context, "--seed", str(seed), "--out", out]
        for k, v in skills:
            cmd += ["--skill", f"{k}={v}"]
        for k, v in sets:
            cmd += ["--set", f"{k}={v}"]
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
        successes += int(info["success"])
        assert info["success"] != info["time_out"], info
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
        expected = self.check(PAPER, t, "T", "DC6", skills={"Phi_SG": sg})
        # policy.make() binds the skill the file embeds, as roger eval --policy does: no skills= needed.
        policy = roger.load_policy(t)
        self.assertEqual(policy.skills, ("Phi_SG",))
        details = {}
        self.assertEqual(python_eval(policy.make(), policy, 20, FIRST_SEED, details)[0], expected["successes"])
        self.assertEqual(details["time_mean"], expected["time_mean"])

    def test_policy_trained_with_sets_replays_in_policy_make(self):
        # Found by a probe: a policy trained with --set replayed differently in Python than in
        # roger eval, which sets the trial's own parameters (those of the file's extra.params that
        # differ from the stage's and context's); policy.make() makes that environment.
        policy_file = train(EXAMPLE, "Look", "Gaze", 3, "look-far", sets=[("robot_distance", "1.9")])
        expected = roger_eval(EXAMPLE, policy_file, 20, FIRST_SEED)
        policy = roger.load_policy(policy_file)
        self.assertEqual(policy.params, {"robot_distance": "1.9"})
        self.assertEqual((policy.curriculum, policy.skills), (EXAMPLE, ()))
        details = {}
        env = policy.make()
        self.assertEqual(env.stage_info["params"]["robot_distance"], 1.9)
        self.assertEqual(python_eval(env, policy, 20, FIRST_SEED, details)[0], expected["successes"])
        self.assertEqual(details["time_mean"], expected["time_mean"])
        self.assertEqual(details["usage"], expected["usage"])
        # The same through make(..., policy=...), in a copy, and in a batch.
        same = copy.deepcopy(roger.make(EXAMPLE, "Look", "Gaze", policy=policy_file))
        python_eval(same, policy, 20, FIRST_SEED, details)
        self.assertEqual(details["time_mean"], expected["time_mean"])
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", 2, policy=policy)
        obs, _ = vec.reset(seed=FIRST_SEED)
        np.testing.assert_array_equal(obs[1], env.reset(seed=FIRST_SEED + 1)[0])
        # Without them the worlds are the stage's own: not what roger eval played.
        python_eval(roger.make(EXAMPLE, "Look", "Gaze"), policy, 20, FIRST_SEED, details)
        self.assertNotEqual(details["time_mean"], expected["time_mean"])
        # params given win over the trial's, as roger eval's --set does.
        self.assertEqual(policy.make(params={"robot_distance": 1.2}).stage_info["params"]["robot_distance"], 1.2)
        with self.assertRaises(roger.RogerError) as cm:
            roger.make(PAPER, "T", "B2", policy=policy_file)
        self.assertIn("is of stage Look context Gaze, not of stage T context B2", str(cm.exception))
        with self.assertRaises(roger.RogerError) as cm:
            policy.make(stage="T")
        self.assertIn("the policy gives stage", str(cm.exception))


    def test_teacher_stage_matches_eval_without_its_teacher(self):
        # roger eval runs a policy in the stage's own worlds, never a teacher's tasks: on a stage
        # with a task space, a seeded reset asks the teacher for a task, so only teacher=False
        # replays roger eval (docs/python.md, The environment).
        policy_file = train(EXAMPLE, "Look", "Gaze", 3, "look")
        expected = roger_eval(EXAMPLE, policy_file, 20, FIRST_SEED)
        policy = roger.load_policy(policy_file)
        details = {}
        untaught = roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS, teacher=False)
        self.assertEqual(python_eval(untaught, policy, 20, FIRST_SEED, details)[0], expected["successes"])
        self.assertEqual(details["time_mean"], expected["time_mean"])
        taught = roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS)
        python_eval(taught, policy, 20, FIRST_SEED, details)
        self.assertNotEqual(details["time_mean"], expected["time_mean"])  # the teacher's worlds


def single_replay(env, seed, n, actions, mode):
    """What environment i of a vector does, replayed on one Env: its first episode in world `seed`,
    the next in seed + n, ...; per step (obs, reward, terminated, seed, ended episode's reward or
    None, final obs or None), under autoreset `mode` ("NextStep" or "SameStep")."""
    obs, info = env.reset(seed=seed)
    rows, pending = [], False
    for a in actions:
        if pending:  # NEXT_STEP: the step after an end only begins the next episode
            seed += n
            obs, info = env.reset(seed=seed)
            rows.append((obs, 0.0, False, seed, None, None))
            pending = False
            continue
        obs, reward, terminated, truncated, info = env.step(int(a))
        assert not truncated
        ended_reward, final = (info["episode_reward"], obs) if terminated else (None, None)
        row_seed = seed
        if terminated and mode == "SameStep":
            seed += n
            obs, _ = env.reset(seed=seed)
            row_seed = seed
        pending = terminated and mode == "NextStep"
        rows.append((obs, reward, terminated, row_seed, ended_reward, final))
    return rows


class VecDeterminism(unittest.TestCase):
    """make_vec: the same episodes with 1 and 2 threads, and the same as single environments, in
    each autoreset mode."""

    N, STEPS = 4, 120

    def run_vec(self, threads, mode="NextStep"):
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=self.N, threads=threads, autoreset_mode=mode)
        self.assertEqual(vec.threads, threads)
        rng = np.random.default_rng(5)
        obs, info = vec.reset(seed=100)
        steps = []
        for _ in range(self.STEPS):
            actions = rng.integers(0, len(vec.actions), size=self.N)
            steps.append((actions, *vec.step(actions)))
        return obs, info, steps

    def test_one_and_two_threads(self):
        for mode in ("NextStep", "SameStep"):
            (obs1, info1, one), (obs2, info2, two) = self.run_vec(1, mode), self.run_vec(2, mode)
            np.testing.assert_array_equal(obs1, obs2)
            np.testing.assert_array_equal(info1["seed"], info2["seed"])
            for a, b in zip(one, two):
                for x, y in zip(a[:5], b[:5]):
                    np.testing.assert_array_equal(x, y)
                for key in ("seed", "sim_seconds", "ticks", "decisions"):
                    np.testing.assert_array_equal(a[5][key], b[5][key])
            ended = sum(int(np.count_nonzero(step[3])) for step in one)  # the terminated column
            self.assertGreater(ended, self.N, mode)  # auto-reset was exercised

    def check_against_single(self, mode):
        obs0, info0, steps = self.run_vec(2, mode)
        env = roger.make(EXAMPLE, "Look", "Gaze")
        for i in range(self.N):
            self.assertEqual(info0["seed"][i], 100 + i)
            rows = single_replay(env, 100 + i, self.N, [step[0][i] for step in steps], mode)
            np.testing.assert_array_equal(env.reset(seed=100 + i)[0], obs0[i])
            for k, ((_, obs, rew, term, trunc, info), row) in enumerate(zip(steps, rows)):
                where = f"{mode}: environment {i}, step {k}"
                # As Gymnasium's _add_info: the keys of ended episodes only in a step where one ended.
                ended_keys = ("_final_obs", "final_obs", "final_info") if mode == "SameStep" else (
                    "episode_reward", "_episode_reward", "success", "is_success", "time_out")
                for key in ended_keys:
                    self.assertEqual(key in info, bool(term.any()), (where, key))
                np.testing.assert_array_equal(obs[i], row[0], where)
                self.assertEqual((rew[i], bool(term[i]), bool(trunc[i]), info["seed"][i]),
                                 (row[1], row[2], False, row[3]), where)
                if not term.any():
                    continue
                if mode == "SameStep":
                    self.assertEqual(bool(info["_final_obs"][i]), row[2], where)
                    if row[2]:
                        np.testing.assert_array_equal(info["final_obs"][i], row[5], where)
                        self.assertEqual(info["final_info"]["episode_reward"][i], row[4], where)
                        self.assertTrue(info["final_info"]["_episode_reward"][i], where)
                    else:
                        self.assertIsNone(info["final_obs"][i], where)
                else:
                    self.assertEqual(bool(info["_episode_reward"][i]), row[2], where)
                    if row[2]:
                        self.assertEqual(info["episode_reward"][i], row[4], where)

    def test_next_step_autoreset_as_single_environments(self):
        self.check_against_single("NextStep")

    def test_same_step_autoreset_as_single_environments(self):
        self.check_against_single("SameStep")


class Interface(unittest.TestCase):
    """Spaces, info, the per-tick mode."""

    def test_bench_times_every_engine_call(self):
        # Found by a probe: scripts/bench_python.py timed the engine's reset and step alone, so the
        # world building of Env.reset (reset_task) was counted as Python's share (+39% for +17%).
        spec = importlib.util.spec_from_file_location("bench_python", "scripts/bench_python.py")
        bench = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(bench)

        class Inner:
            def reset_task(self, seed, task):
                time.sleep(0.05)
                return seed

            @property
            def sim_seconds(self):
                time.sleep(0.05)
                return 1.0
        engine = bench.TimedEngine(Inner())
        self.assertEqual(engine.reset_task(3, []), 3)
        self.assertEqual(engine.sim_seconds, 1.0)
        self.assertGreaterEqual(engine.seconds, 0.1)
        # As the benchmark uses it: an Env whose every engine call is timed runs as before.
        env = roger.make(EXAMPLE, "Look", "Gaze")
        env._env = engine = bench.TimedEngine(env._env)
        env.reset(seed=1)
        env.step(0)
        self.assertGreater(engine.seconds, 0.0)
        # Found by a probe: the installed copy looked for build/engine/roger in the current folder
        # and died with a traceback after half its measurements; it finds roger as the figure
        # scripts do, and a missing one is one line before anything runs.
        r = subprocess.run([sys.executable, "scripts/bench_python.py", "--roger", "/nonexistent/roger"],
                           capture_output=True, text=True)
        self.assertNotEqual(r.returncode, 0)
        self.assertEqual(r.stderr.strip(), "bench_python.py: --roger /nonexistent/roger: no such program")

    def test_paper_ids_map_the_registered_ids(self):
        # docs/python.md's loop over roger.PAPER_IDS, which was undocumented (found by a probe).
        self.assertEqual(sorted(roger.PAPER_IDS), sorted(
            [f"roger/SG-{c}-v0" for c in ("B1", "DC1", "DC2")] +
            [f"roger/T-{c}-v0" for c in ("B2", "DC3", "DC4", "DC5", "DC6")]))
        with open("docs/python.md") as f:
            self.assertIn("for env_id, (stage, context) in roger.PAPER_IDS.items()", f.read())
        for env_id, (stage, context) in roger.PAPER_IDS.items():
            if stage == "SG":
                env = roger.make("paper", stage, context)
                env.reset(seed=1)
                self.assertEqual((env.stage_info["stage"], env.stage_info["context"]), (stage, context))
                env.close()

    def test_dir_lists_the_public_names(self):
        # Found by a probe: dir(roger) listed the modules it imports for itself (np, os, copy, ...).
        public = [n for n in dir(roger) if not n.startswith("_")]
        self.assertEqual(sorted(public), sorted(roger.__all__))
        for name in ("make", "make_vec", "load_policy", "axis", "Axis", "RogerError", "spaces"):
            self.assertIn(name, public)
        for name in ("np", "os", "copy", "threading"):
            self.assertNotIn(name, public)

    def test_version_and_project_folder(self):
        # Found by a probe: the package named neither its version nor the project folder it reads.
        out = subprocess.run([ROGER, "--version"], capture_output=True, text=True, check=True).stdout
        self.assertEqual(out.strip(), "roger %s (project folder: %s)" % (roger.__version__, roger.project_folder()))

    def test_docs_example_is_the_example_file(self):
        # Found by a probe: the guide's copy of docs/examples/python_example.py said "a runs until
        # the next decision point" where the file says "a runs until the state changes".
        with open("docs/python.md") as f:
            section = f.read().split("## A complete example", 1)[1]
        code = section.split("```python\n", 1)[1].split("```", 1)[0]
        with open("docs/examples/python_example.py") as f:
            lines = set(f.read().splitlines())
        self.assertEqual([line for line in code.splitlines() if line not in lines], [])

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
        # The scenario's parameters were all str ("0.25" * 2 is "0.250.25"): each is its declared type.
        params = env.stage_info["params"]
        self.assertEqual((params["goal_radius"], params["eye_pixels"], params["shape"], params["locked"]),
                         (0.25, 128, "circle", ""))
        self.assertEqual((type(params["goal_x"]), type(params["eye_pixels"])), (float, int))
        # A list parameter given as a list, as it reads back joined (found by a probe: its repr was
        # given to the scenario, which refused "['left_eye', 'right_eye']").
        for locked in (["left_eye", "right_eye"], ("left_eye", "right_eye"), "left_eye,right_eye"):
            with roger.make(EXAMPLE, "Look", "Gaze", params={"locked": locked}) as given:
                self.assertEqual(given.stage_info["params"]["locked"], "left_eye,right_eye")

    def test_step_outside_an_episode_says_which_case(self):
        # Found by a probe: after an episode ended, step said "no episode is running ... (call
        # reset first)", though reset had been called.
        env = roger.make(EXAMPLE, stage="Look", context="Gaze")
        self.assertRaisesRegex(roger.RogerError, r"no episode is running in Look/Gaze \(call reset first\)",
                               env.step, 0)
        env.reset(seed=7)
        done = False
        while not done:
            _, _, terminated, truncated, _ = env.step(1)
            done = terminated or truncated
        self.assertRaisesRegex(roger.RogerError, r"the episode in Look/Gaze is over \(it ended with terminated or "
                               r"truncated; call reset for the next\)", env.step, 0)
        env.reset(seed=8)
        env.step(0)

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

    def test_tick_mode_images_follow_the_body(self):
        # Eyes of 32 pixels (docs/scenarios.md, Bodies): the observations and their space say so.
        env = roger.make(EXAMPLE, stage="Look", context="Gaze", mode="tick", params={"eye_pixels": 32})
        self.assertEqual(env.observation_space["images"].shape, (2, 32, 3))
        obs, info = env.reset(seed=7)
        self.assertEqual(obs["images"].shape, (2, 32, 3))
        self.assertEqual(obs["stimulus"].shape, (2, 32))
        obs, reward, terminated, truncated, info = env.step(0)
        self.assertTrue(env.observation_space.contains(obs))


    def test_tick_mode_pays_the_lua_reward_per_tick(self):
        # Every tick is a decision in tick mode, so a Lua reward's "decision" cost (-1 in the
        # tutorial's stage) is paid at every tick: returns are not decision mode's (docs/python.md).
        env = roger.make(EXAMPLE, "Look", "Gaze", mode="tick")
        env.reset(seed=7)
        rewards = [env.step(0)[1] for _ in range(5)]
        self.assertEqual(rewards, [-1.0] * 5)

    def test_tick_mode_refuses_a_body_outside_its_space(self):
        # The space is made from the stage's body; a teacher that sets the eyes' pixels (LCAS lifts
        # eye_pixels from 32) would give images outside it. Found by a probe: make accepted the
        # stage and then refused every reset; make refuses it, naming the teacher and its line.
        with self.assertRaises(roger.RogerError) as cm:
            roger.make(TEACHERS, "SG_lcas", "B1", mode="tick")
        for text in ("make: mode='tick' observes the stage's body", "roger.teacher.lcas (", "teachers.lua:87)",
                     "lifts eye_pixels through 32, 64, 128", "eyes of 32 pixels", "have 128 (stage_info['eye_pixels'])",
                     "teacher=False", "mode='decision'"):
            self.assertIn(text, str(cm.exception))
        with self.assertRaises(roger.RogerError) as cm:  # a teacher given to make, likewise
            roger.make(EXAMPLE, "Look", "Gaze", mode="tick", teacher="roger.teacher.lcas{lift = {eye_pixels = {64, 128}}}")
        self.assertIn("roger.teacher.lcas (make(teacher=...):1), lifts eye_pixels through 64, 128", str(cm.exception))
        # A teacher that keeps the body (it lifts another parameter) is not refused.
        roger.make(EXAMPLE, "Look", "Gaze", mode="tick", teacher="roger.teacher.lcas{lift = {robot_distance = {1, 1.5}}}")
        obs, _ = roger.make(TEACHERS, "SG_lcas", "B1", mode="tick", teacher=False).reset(seed=1)
        self.assertEqual(obs["images"].shape, (2, 128, 3))
        self.assertEqual(roger.make(TEACHERS, "SG_lcas", "B1").reset(seed=1)[1]["task_params"], {"eye_pixels": 32})
        # A task space over eye_pixels is refused at make.
        with self.assertRaises(roger.RogerError) as cm:
            roger.make(EXAMPLE, "Look", "Gaze", mode="tick", tasks={"eye_pixels": roger.axis.int(32, 40)})
        self.assertIn("the task space varies eye_pixels (roger.int(32, 40))", str(cm.exception))


class GymnasiumApi(unittest.TestCase):
    """One environment as Gymnasium 1.x users expect it, with or without gymnasium installed."""

    def test_time_out_is_terminal(self):
        # Searching for ever never converges phi0: the episode runs to the stage's time-out, which
        # pays -100 and ends the episode as the engine's learner treats it (terminated, not truncated).
        env = roger.make(EXAMPLE, "Look", "Gaze")
        env.reset(seed=3)
        terminated = truncated = False
        while not terminated:
            obs, reward, terminated, truncated, info = env.step(0)
            self.assertFalse(truncated)
        self.assertTrue(info["time_out"])
        self.assertFalse(info["success"])
        self.assertEqual(reward, -100.0)
        self.assertAlmostEqual(info["sim_seconds"], env.stage_info["time_limit"])
        # ...and the absorbing state is terminal without a time-out.
        env.reset(seed=3)
        for _ in range(100):
            obs, reward, terminated, truncated, info = env.step(1)
            if terminated:
                break
        self.assertTrue(terminated)
        self.assertEqual(info["time_out"], not info["success"])

    def test_metadata_np_random_and_context_manager(self):
        with roger.make(EXAMPLE, "Look", "Gaze") as env:
            self.assertEqual(env.metadata["render_modes"], ["rgb_array"])
            self.assertGreater(env.metadata["render_fps"], 0)
            self.assertIsNone(env.render_mode)
            self.assertIs(env.unwrapped, env)
            env.reset(seed=11)
            first = env.np_random.integers(1 << 30, size=4)
            env.reset(seed=11)
            np.testing.assert_array_equal(env.np_random.integers(1 << 30, size=4), first)
            env.reset()  # an unseeded reset does not seed it again: it runs on, as Gymnasium's
            reference = np.random.default_rng(11)  # = gymnasium.utils.seeding.np_random(11)
            np.testing.assert_array_equal(reference.integers(1 << 30, size=4), first)
            np.testing.assert_array_equal(env.np_random.integers(1 << 30, size=4), reference.integers(1 << 30, size=4))
            env.reset(seed=12)
            self.assertFalse(np.array_equal(env.np_random.integers(1 << 30, size=4), first))
        self.assertRaisesRegex(roger.RogerError, "closed", env.step, 0)  # the with block closed it
        self.assertRaisesRegex(roger.RogerError, "closed", env.reset, seed=1)
        env.close()  # closing twice is allowed

    def test_wrapper_attributes_and_stage_info_copies(self):
        # Found by a probe: without gymnasium, Env lacked Gymnasium 1.x's get_wrapper_attr,
        # has_wrapper_attr and set_wrapper_attr (the stand-in base, Bare, has them now); and
        # stage_info was one dict whose edits stuck but changed nothing.
        from roger import _base

        class Bare(_base.Env):
            pass

        env = roger.make(EXAMPLE, "Look", "Gaze")
        for e in (env, Bare()):
            with self.subTest(env=type(e).__name__):
                self.assertTrue(e.has_wrapper_attr("metadata"))
                self.assertFalse(e.has_wrapper_attr("nothing"))
                self.assertIs(e.get_wrapper_attr("metadata"), e.metadata)
                self.assertRaises(AttributeError, e.get_wrapper_attr, "nothing")
                self.assertFalse(e.set_wrapper_attr("nothing", 1, force=False))
                self.assertFalse(hasattr(e, "nothing"))
                self.assertTrue(e.set_wrapper_attr("nothing", 1))
                self.assertEqual(e.nothing, 1)
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=2, threads=1)
        for e in (env, vec):
            info = e.stage_info
            limit, alpha = info["time_limit"], info["learner"]["alpha"]
            info["time_limit"], info["learner"]["alpha"] = -1, 9
            self.assertEqual((e.stage_info["time_limit"], e.stage_info["learner"]["alpha"]), (limit, alpha))
            self.assertEqual(copy.deepcopy(e).stage_info, e.stage_info)

    def test_unseeded_reset_goes_on(self):
        env = roger.make(EXAMPLE, "Look", "Gaze")
        env.reset(seed=123)
        _, info = env.reset()
        self.assertEqual(info["seed"], roger.mix(123, 1) >> 1)  # the stream of seed 123 (DeepRL has the rule)
        env.reset(options={})  # empty options are accepted (the stage knows none)

    def test_render_rgb_array(self):
        env = roger.make(EXAMPLE, "Look", "Gaze", render_mode="rgb_array", render_width=300)
        self.assertEqual(env.render_mode, "rgb_array")
        self.assertRaisesRegex(roger.RogerError, "reset first", env.render)
        env.reset(seed=5)
        frame = env.render()
        self.assertEqual(frame.dtype, np.uint8)
        self.assertEqual(frame.ndim, 3)
        self.assertEqual(frame.shape[1:], (300, 3))
        self.assertGreater(frame.shape[0], 300)  # the arena and the eye strips below it
        self.assertGreater(len(np.unique(frame.reshape(-1, 3), axis=0)), 10)  # a picture, not a blank
        env.step(0)
        self.assertFalse(np.array_equal(env.render(), frame))  # the robot moved
        # No render_mode: nothing, and a warning says why, as Gymnasium's own environments do.
        with self.assertWarnsRegex(UserWarning, r"render_mode is None\); make it with make\(\.\.\., "
                                                r"render_mode='rgb_array'\)"):
            self.assertIsNone(roger.make(EXAMPLE, "Look", "Gaze").render())
        self.assertRaisesRegex(roger.RogerError, "render_mode", roger.make, EXAMPLE, "Look", "Gaze",
                               render_mode="human")

    def test_render_is_roger_render(self):
        # The picture is `roger render`'s of the same world: the scenario at the seed, not yet moved.
        env = roger.make(EXAMPLE, "Look", "Gaze", render_mode="rgb_array", render_width=400)
        env.reset(seed=9)
        png = os.path.join(WORK, "render-9.png")
        subprocess.run([ROGER, "render", "scenarios/unobstructed.lua", "--seed", "9", "--width", "400", "--out", png],
                       check=True, capture_output=True)
        np.testing.assert_array_equal(env.render(), read_png(png))

    def test_tick_mode_render_fps(self):
        env = roger.make(EXAMPLE, "Look", "Gaze", mode="tick")
        self.assertEqual(env.metadata["render_fps"], round(1 / env.stage_info["tick_seconds"]))


    def test_info_seed_is_uint64(self):
        # Found by a probe: info["seed"] was a Python int, which Gymnasium's sync and async vector
        # environments gather in an int64 array: a seed of 2^63 or more overflowed there. It is a
        # numpy.uint64, as make_vec's info["seed"] is.
        env = roger.make(EXAMPLE, "Look", "Gaze")
        for seed in (0, 2 ** 63, 2 ** 64 - 1):
            _, info = env.reset(seed=seed)
            self.assertIsInstance(info["seed"], np.uint64)
            self.assertEqual(info["seed"], seed)
        self.assertIsInstance(env.step(0)[4]["seed"], np.uint64)
        _, info = env.reset()
        self.assertIsInstance(info["seed"], np.uint64)
        self.assertEqual(roger.make_vec(EXAMPLE, "Look", "Gaze", 2).reset(seed=1)[1]["seed"].dtype, np.uint64)

    def test_stand_in_spaces_compare_mask_and_serialize(self):
        # Found by a probe: the stand-in spaces had no ==, no sample(mask=..., probability=...) and
        # no to_jsonable, and a batch's observation_space was a MultiDiscrete without gymnasium, a
        # Box with it. They follow gymnasium 1.x's now (the same samples where it is importable).
        from roger import _spaces as S
        self.assertEqual(S.Discrete(3), S.Discrete(3))
        self.assertNotEqual(S.Discrete(3), S.Discrete(3, start=1))
        self.assertEqual(S.MultiDiscrete([3, 3]), S.MultiDiscrete(np.full(2, 3)))
        self.assertNotEqual(S.MultiDiscrete([3, 3]), S.MultiDiscrete([3, 2]))
        self.assertEqual(S.Box(0, 2, (2, 3), np.int64), S.Box(np.zeros((2, 3)), np.full((2, 3), 2), dtype=np.int64))
        self.assertNotEqual(S.Box(0, 1, (2,)), S.Box(0, 2, (2,)))
        self.assertEqual(S.Dict({"a": S.Discrete(2)}), S.Dict({"a": S.Discrete(2)}))
        d = S.Discrete(4, seed=0)
        self.assertEqual({int(d.sample(mask=np.array([0, 0, 1, 0], np.int8))) for _ in range(5)}, {2})
        self.assertEqual(d.sample(mask=np.zeros(4, np.int8)), 0)
        self.assertEqual({int(d.sample(probability=np.array([0, 1.0, 0, 0]))) for _ in range(5)}, {1})
        self.assertRaises(ValueError, d.sample, mask=np.ones(4, np.int8), probability=np.full(4, 0.25))
        m = S.MultiDiscrete([3, 3], seed=0)
        self.assertEqual(m.sample(mask=(np.array([0, 0, 1], np.int8), np.array([1, 0, 0], np.int8))).tolist(), [2, 0])
        self.assertRaises(S.Error, S.Box(0, 1, (2,)).sample, mask=np.ones(2, np.int8))
        self.assertEqual(d.to_jsonable([np.int64(1), np.int64(3)]), [1, 3])
        self.assertEqual(m.from_jsonable(m.to_jsonable([np.array([1, 2])]))[0].tolist(), [1, 2])
        t = S.Dict({"a": S.Discrete(2), "b": S.Box(0.0, 1.0, (), np.float64)})
        self.assertEqual(t.to_jsonable([{"a": np.int64(1), "b": np.array(0.5)}]), {"a": [1], "b": [0.5]})
        self.assertEqual(repr(t.from_jsonable({"a": [1], "b": [0.5]})), repr([{"a": np.int64(1), "b": np.array(0.5)}]))
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", 3)
        self.assertEqual(type(vec.observation_space).__name__, "Box")
        self.assertEqual(repr(vec.observation_space), "Box(0, 2, (3, 2), int64)")
        self.assertEqual(repr(vec.action_space), "MultiDiscrete([2 2 2])")
        obs, _ = vec.reset(seed=1)
        self.assertIn(obs, vec.observation_space)
        try:
            gym_spaces = importlib.import_module("gymnasium.spaces")
        except ImportError:
            return
        for make, kwargs in ((lambda M: M.Discrete(5, seed=3), {"mask": np.array([1, 0, 1, 1, 0], np.int8)}),
                             (lambda M: M.Discrete(3, seed=3), {"probability": np.array([0.2, 0.3, 0.5])}),
                             (lambda M: M.MultiDiscrete([3, 2], seed=3),
                              {"probability": (np.array([0.2, 0.3, 0.5]), np.array([0.5, 0.5]))}),
                             (lambda M: M.Dict({"a": M.Discrete(3), "b": M.Discrete(2)}, seed=3),
                              {"mask": {"a": np.array([1, 1, 0], np.int8), "b": np.array([0, 1], np.int8)}})):
            ours, theirs = make(S), make(gym_spaces)
            self.assertEqual(repr([ours.sample(**kwargs) for _ in range(5)]),
                             repr([theirs.sample(**kwargs) for _ in range(5)]))
        box = gym_spaces.Box(0, 2, (3, 2), np.int64)
        self.assertEqual(repr(box), repr(vec.observation_space))

    def test_stand_in_spaces_refuse_what_gymnasiums_refuse(self):
        # Found by a probe: Discrete(0), Discrete(3.0), MultiDiscrete([0, 3]), Box(1, 0, (2,)) and
        # Dict({"a": 3}) were made, which gymnasium 1.x refuses, with these errors.
        from roger import _spaces as S
        for make, error, text in ((lambda: S.Discrete(0), ValueError, "n (counts) have to be positive"),
                                  (lambda: S.Discrete(-1), ValueError, "n (counts) have to be positive"),
                                  (lambda: S.Discrete(3.0), TypeError, "Expects `n` to be an integer"),
                                  (lambda: S.Discrete(3, start=0.5), TypeError, "Expects `start` to be an integer"),
                                  (lambda: S.MultiDiscrete([0, 3]), ValueError, "nvec (counts) have to be positive"),
                                  (lambda: S.MultiDiscrete([2, 3], start=[0]), ValueError, "the same shape"),
                                  (lambda: S.Box(1, 0, (2,)), ValueError, "low values must be less than or equal"),
                                  (lambda: S.Box(np.nan, 1, (2,)), ValueError, "No low value can be equal to `np.nan`"),
                                  (lambda: S.Dict({"a": 3}), TypeError, "Dict space element is not an instance")):
            self.assertRaisesRegex(error, re.escape(text), make)
        self.assertEqual(S.Discrete(np.int64(3), start=np.int32(1)).n, 3)  # numpy integers are integers
        for bound in (10**30, -2**63 - 1):
            self.assertRaisesRegex(roger.RogerError, "within Lua's 64-bit integers", roger.axis.int, 0 if bound > 0 else bound,
                                   bound if bound > 0 else 0)

    def test_stand_in_spaces_are_gymnasiums(self):
        # The package's own spaces (used without gymnasium) seed, sample and hold members as
        # gymnasium 1.x's do; where gymnasium is importable, the same seeds give the same samples.
        from roger import _spaces as S
        tasks = S.Dict({"shape": S.Discrete(4), "distance": S.Box(0.8, 2.0, (), np.float64),
                        "obstacles": S.Discrete(7, start=1)})
        self.assertEqual(list(tasks.spaces), ["distance", "obstacles", "shape"])  # sorted, as gymnasium's
        tasks.seed(0)
        first = [tasks.sample() for _ in range(3)]
        tasks.seed(0)
        self.assertEqual(repr(first), repr([tasks.sample() for _ in range(3)]))
        self.assertEqual(repr(S.Dict(tasks.spaces, seed=5).sample()), repr(S.Dict(tasks.spaces, seed=5).sample()))
        self.assertTrue(all(tasks.contains(t) for t in first))
        d = S.Discrete(3, seed=1)
        self.assertIsInstance(d.sample(), np.int64)
        for member in (1, np.array(1), np.int8(2)):
            self.assertTrue(d.contains(member), member)
        for other in (3, 1.0, np.array([1]), np.array(1, np.uint64)):
            self.assertFalse(d.contains(other), other)
        m = S.MultiDiscrete(np.full(2, 3))
        for member in ([1, 2], np.array([1, 2], np.int32), np.array([0, 2], np.uint8)):
            self.assertTrue(m.contains(member), member)
        for other in ([1, 3], np.array([1.0, 2.0]), np.array([1, 2], np.uint64), [1, 2, 0]):
            self.assertFalse(m.contains(other), other)  # floats do not cast to int64 safely (gymnasium 1.2.3+)
        box = S.Box(np.zeros(3, np.float32), np.ones(3, np.float32))
        self.assertEqual((box.shape, box.dtype), ((3,), np.float32))
        self.assertEqual(S.Box(0, 1).shape, (1,))
        try:
            gym_spaces = importlib.import_module("gymnasium.spaces")
        except ImportError:
            return
        for make in (lambda M: M.Dict({"shape": M.Discrete(4), "distance": M.Box(0.8, 2.0, (), np.float64)}, seed=3),
                     lambda M: M.MultiDiscrete(np.full(4, 3), seed=3),
                     lambda M: M.Box(np.array([0., -np.inf, 0.]), np.array([1., 1., np.inf]), seed=3),
                     lambda M: M.Box(0, 255, (2, 3), np.uint8, seed=3)):
            ours, theirs = make(S), make(gym_spaces)
            self.assertEqual(repr([ours.sample() for _ in range(3)]), repr([theirs.sample() for _ in range(3)]))
            self.assertEqual(repr(ours), repr(theirs))


def read_png(path):
    """An 8-bit RGB or RGBA PNG (what cairo writes) as an H x W x 3 uint8 array, with zlib alone."""
    import struct
    import zlib
    with open(path, "rb") as f:
        data = f.read()
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour = header[:4]
    assert depth == 8 and colour in (2, 6), header
    channels = 3 if colour == 2 else 4
    raw, stride = zlib.decompress(idat), width * channels
    rows, prev = [], np.zeros(stride, np.int32)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], np.frombuffer(raw, np.uint8, stride, y * (stride + 1) + 1).astype(np.int32)
        if kind == 0:
            cur = line
        elif kind == 2:
            cur = (line + prev) & 255
        else:  # Sub, Average, Paeth: left-neighbour filters, one byte at a time
            cur = np.zeros(stride, np.int32)
            for i in range(stride):
                a = cur[i - channels] if i >= channels else 0
                b, c = prev[i], (prev[i - channels] if i >= channels else 0)
                if kind == 1:
                    pred = a
                elif kind == 3:
                    pred = (a + b) // 2
                else:
                    p = a + b - c
                    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                    pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                cur[i] = (line[i] + pred) & 255
        rows.append(cur)
        prev = cur
    return np.array(rows, np.uint8).reshape(height, width, channels)[:, :, :3]


class VectorApi(unittest.TestCase):
    """make_vec as Gymnasium 1.x's vector environments: autoreset modes, seeds, masks, render, faults."""

    def make(self, n=3, **kwargs):
        return roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=n, threads=2, **kwargs)

    def test_metadata_and_default_mode(self):
        vec = self.make()
        self.assertEqual(vec.metadata["autoreset_mode"], roger.AutoresetMode.NEXT_STEP)
        self.assertEqual(vec.metadata["autoreset_mode"].value, "NextStep")
        self.assertEqual(vec.single_action_space.n, 2)
        self.assertEqual(vec.action_space.shape, (3,))
        self.assertEqual(vec.observation_space.shape, (3, 2))
        for mode in roger.AutoresetMode:
            self.assertEqual(self.make(autoreset_mode=mode).metadata["autoreset_mode"], mode)
        self.assertRaisesRegex(roger.RogerError, "autoreset_mode", self.make, autoreset_mode="Sometimes")

    def test_next_step_autoreset_ignores_the_action(self):
        vec = self.make(1)
        vec.reset(seed=3)
        terminated = np.array([False])
        while not terminated[0]:
            obs, reward, terminated, truncated, info = vec.step(np.array([0]))
        self.assertTrue(info["time_out"][0] and info["_time_out"][0])
        # Out of range, it is refused even here (found by a probe: it was accepted silently)...
        self.assertRaisesRegex(roger.RogerError, r"action 7 of environment 0 is not in \[0, 2\)", vec.step, np.array([7]))
        obs, reward, terminated, truncated, info = vec.step(np.array([1]))  # ...in range, ignored
        self.assertEqual((reward[0], terminated[0], truncated[0]), (0.0, False, False))
        self.assertEqual(info["seed"][0], 4)  # the next seed of its schedule (seed + num_envs)
        self.assertEqual(info["ticks"][0], 0)

    def test_unseeded_reset_goes_on_and_seed_lists(self):
        vec = self.make()
        _, info = vec.reset()
        np.testing.assert_array_equal(info["seed"], [0, 1, 2])
        _, info = vec.reset()  # not the same worlds again
        np.testing.assert_array_equal(info["seed"], [3, 4, 5])
        _, info = vec.reset(seed=10)
        np.testing.assert_array_equal(info["seed"], [10, 11, 12])
        _, info = vec.reset(seed=[7, None, 40])
        np.testing.assert_array_equal(info["seed"], [7, 14, 40])
        self.assertRaisesRegex(roger.RogerError, "one per environment", vec.reset, seed=[1, 2])
        self.assertRaisesRegex(roger.RogerError, "seed", vec.reset, seed=-1)
        self.assertRaisesRegex(roger.RogerError, "seed", vec.reset, seed=[1, "x", 2])

    def test_unseeded_entries_of_a_seed_list_play_apart(self):
        # Found by a probe: reset(seed=[1, None, 3]) on a fresh batch played world 1 twice (the
        # unseeded entry's schedule starts at 0 + 1). Such an entry now begins a schedule of its own
        # when its own meets a seeded one's (the same residue modulo num_envs), now and later.
        vec = self.make()
        _, info = vec.reset(seed=[1, None, 3])
        seeds = [int(x) for x in info["seed"]]
        self.assertEqual((seeds[0], seeds[2]), (1, 3))
        self.assertEqual(seeds[1], roger.mix(1, 1) >> 1)  # mix(n, k) >> 1 of the world it would have played
        self.assertEqual(len({x % 3 for x in seeds}), 3)  # schedules apart: no autoreset meets another's
        played = set(seeds)
        for _ in range(3):
            _, info = vec.reset()
            self.assertFalse(played & set(int(x) for x in info["seed"]))
            played |= set(int(x) for x in info["seed"])
        np.testing.assert_array_equal(self.make().reset(seed=[1, None, 3])[1]["seed"], seeds)  # deterministic
        # An entry whose schedule meets no seeded one goes on along it, as before.
        vec = self.make()
        vec.reset(seed=10)
        np.testing.assert_array_equal(vec.reset(seed=[7, None, 40])[1]["seed"], [7, 14, 40])

    def worlds_played(self, vec, steps, rng_seed=3):
        """The worlds each environment of `vec` plays in `steps` random steps after a reset, in order
        (NEXT_STEP autoreset: an episode's first step has ticks 0)."""
        n, rng = vec.num_envs, np.random.default_rng(rng_seed)
        worlds = [[] for _ in range(n)]
        for _ in range(steps):
            _, _, _, _, info = vec.step(rng.integers(0, 2, size=n))
            for i in range(n):
                if info["ticks"][i] == 0:
                    worlds[i].append(int(info["seed"][i]))
        return worlds

    def test_given_seeds_whose_schedules_meet_play_apart(self):
        # Found by a probe: reset(seed=[1, 4, 7]) of 3 environments played 1, 4, 7, 10 in
        # environment 0 and 4, 7, 10, 13 in environment 1 (seeds S_i + k * num_envs of one residue).
        # Each plays its seed first; of those of one residue the highest seed's goes on along its
        # schedule, the others on schedules of their own.
        vec = self.make()
        _, info = vec.reset(seed=[1, 4, 7])
        np.testing.assert_array_equal(info["seed"], [1, 4, 7])
        later = self.worlds_played(vec, 400)
        worlds = [[s] + w for s, w in zip((1, 4, 7), later)]
        played = [x for w in worlds for x in w]
        self.assertGreater(len(played), 20)
        self.assertEqual(len(played), len(set(played)), worlds)
        self.assertEqual(worlds[2][:3], [7, 10, 13])  # the highest seed goes on along its schedule
        def own(second, taken):  # mix(n, k) >> 1, n the seed it would have played second, k the first apart
            return next(roger.mix(second, k) >> 1 for k in range(1, 100) if (roger.mix(second, k) >> 1) % 3 not in taken)
        w0 = own(4, {1})
        w1 = own(7, {1, w0 % 3})
        self.assertEqual((worlds[0][1:3], worlds[1][1:3]), ([w0, w0 + 3], [w1, w1 + 3]))
        twin = pickle.loads(pickle.dumps(vec))  # a copy keeps the schedules
        np.testing.assert_array_equal(twin.step(np.zeros(3, int))[4]["seed"], vec.step(np.zeros(3, int))[4]["seed"])
        again = self.make()  # deterministic
        again.reset(seed=[1, 4, 7])
        self.assertEqual(self.worlds_played(again, 400), later)
        # Seeds of distinct residues play exactly their schedules, as before.
        for seeds in ([10, 11, 12], [7, 14, 30], [5, 3, 1]):
            with self.subTest(seeds=seeds):
                vec = self.make()
                vec.reset(seed=seeds)
                for i, w in enumerate(self.worlds_played(vec, 150)):
                    self.assertEqual(w, [seeds[i] + 3 * (k + 1) for k in range(len(w))])

    def test_seeds_across_the_wrap_play_apart(self):
        # Found by a probe: schedules were kept apart by their residues modulo num_envs, which the
        # wrap past 2^64 - 1 changes when num_envs does not divide 2^64: 3 environments seeded
        # [2^64 - 1, None, None] played 2^64 - 1, 2, 5, 8 in environment 0, environment 2's worlds one
        # episode behind; a masked reset to 2^64 - 1 after reset(seed=0) alike; and reset(seed=2^64 - 2),
        # whose schedules never meet, moved environment 2 to a schedule of its own.
        top = 2**64 - 1
        own = [roger.mix(2, k) >> 1 for k in range(1, 30)]  # a schedule of its own, from 2
        def played(vec, first):
            return [[int(s)] + w for s, w in zip(first, self.worlds_played(vec, 150))]
        def distinct(worlds):
            flat = [x for w in worlds for x in w]
            self.assertGreater(len(flat), 20)
            self.assertEqual(len(flat), len(set(flat)), worlds)
        vec = self.make()
        _, info = vec.reset(seed=[top, None, None])
        worlds = played(vec, info["seed"])
        distinct(worlds)
        self.assertEqual(worlds[0][:3], [top, 2, 5])  # ahead of environment 2's 2, which moves on at once
        self.assertEqual(worlds[1][:3], [1, 4, 7])
        self.assertIn(worlds[2][0], own)
        vec = self.make()
        vec.reset(seed=0)
        _, info = vec.reset(seed=top, options={"reset_mask": np.array([True, False, False])})
        worlds = played(vec, [top, 1, 2])
        distinct(worlds)
        self.assertEqual((worlds[1][:3], worlds[2][:3]), ([1, 4, 7], [2, 5, 8]))  # ahead of 2^64 - 1: go on
        self.assertIn(worlds[0][1], own)  # from the world it would have played second
        vec = self.make()
        _, info = vec.reset(seed=[top, 2, 100])
        worlds = played(vec, info["seed"])
        distinct(worlds)
        self.assertEqual((worlds[1][:3], worlds[2][:3]), ([2, 5, 8], [100, 103, 106]))
        # An int seed's schedules never meet, across the wrap too: each goes on along its own.
        vec = self.make()
        _, info = vec.reset(seed=2**64 - 2)
        self.assertEqual([w[:3] for w in played(vec, info["seed"])], [[top - 1, 1, 4], [top, 2, 5], [0, 3, 6]])

    def test_step_after_a_failed_reset_says_so(self):
        # Found by a probe: after a batch reset that raised (the scenario's generate erring in each
        # environment's world), step said "environment 0 of 2 has not been reset yet (its reset_mask
        # entry was False at every reset)", which was false.
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=2, threads=1, scenario=GENERATE_FAILS_ONCE)
        with self.assertRaises(roger.ScriptError) as cm:
            vec.reset(seed=4)
        self.assertIn("generate_fails_once: the second world", str(cm.exception))
        with self.assertRaises(roger.RogerError) as cm:
            vec.step(np.zeros(2, int))
        text = str(cm.exception)
        self.assertTrue(text.startswith("step: environment 0 of 2 has no episode: the last reset that asked for it "
                                        "failed (reset: environment 0 of 2 (seed 4): "), text)
        self.assertIn("reset it again", text)
        self.assertNotIn("reset_mask entry was False", text)
        twin = pickle.loads(pickle.dumps(vec))  # a copy says so too
        self.assertRaisesRegex(roger.RogerError, "the last reset that asked for it failed", twin.step, np.zeros(2, int))
        _, info = vec.reset(seed=4)  # the next reset begins them
        np.testing.assert_array_equal(info["seed"], [4, 5])
        vec.step(np.zeros(2, int))
        # One that no reset asked for is still "not reset yet".
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=2, threads=1)
        vec.reset(seed=1, options={"reset_mask": np.array([True, False])})
        self.assertRaisesRegex(roger.RogerError, "environment 1 of 2 has not been reset yet", vec.step,
                               np.zeros(2, int))

    def test_reset_mask(self):
        vec, twin = self.make(), self.make()
        for v in (vec, twin):
            v.reset(seed=10)
            v.step(np.array([0, 0, 0]))
        mask = np.array([False, True, False])
        # World 50 keeps environment 1's residue modulo 3 (11's): no schedule meets another's, so
        # the others go on untouched (51 would meet environment 2's 15, 18, ..., which would then
        # continue apart: test_seeded_reset_keeps_apart_from_those_left_out).
        obs, info = vec.reset(seed=49, options={"reset_mask": mask})
        np.testing.assert_array_equal(info["_seed"], mask)
        self.assertEqual(info["seed"][1], 50)
        single = roger.make(EXAMPLE, "Look", "Gaze")
        np.testing.assert_array_equal(obs[1], single.reset(seed=50)[0])
        obs, reward, _, _, info = vec.step(np.array([0, 0, 0]))
        t_obs, t_reward, _, _, t_info = twin.step(np.array([0, 0, 0]))
        for i in (0, 2):  # the others went on as if nothing had happened
            self.assertEqual((info["seed"][i], reward[i]), (t_info["seed"][i], t_reward[i]))
            np.testing.assert_array_equal(obs[i], t_obs[i])
        for bad in ([True, False, True], np.array([0, 1, 0]), np.zeros(3, bool), np.ones(2, bool)):
            self.assertRaisesRegex(roger.RogerError, "reset_mask", vec.reset, options={"reset_mask": bad})

    def test_disabled_autoreset(self):
        vec = self.make(2, autoreset_mode="Disabled")
        vec.reset(seed=3)
        ended = np.zeros(2, bool)
        while not ended.any():
            _, _, ended, _, info = vec.step(np.array([0, 0]))
        self.assertNotIn("final_obs", info)
        first = int(np.flatnonzero(ended)[0])
        with self.assertRaises(roger.RogerError) as cm:
            vec.step(np.array([0, 0]))
        self.assertIn(f"environment {first}", str(cm.exception))
        self.assertIn("reset_mask", str(cm.exception))
        vec.reset(options={"reset_mask": ended})
        vec.step(np.array([0, 0]))  # steps again

    def test_render_every_environment(self):
        vec = self.make(render_mode="rgb_array", render_width=200)
        vec.reset(seed=1)
        frames = vec.render()
        self.assertEqual(len(frames), 3)
        for f in frames:
            self.assertEqual((f.dtype, f.shape[1:]), (np.uint8, (200, 3)))
        self.assertFalse(np.array_equal(frames[0], frames[1]))  # different worlds
        with self.assertWarnsRegex(UserWarning, r"make it with make_vec\(\.\.\., render_mode='rgb_array'\)"):
            self.assertIsNone(self.make().render())

    def test_render_before_reset_raises(self):
        # An environment of the batch that no reset has begun has no world: rendering it raises,
        # naming it, as Env.render does (it used to read a null world and crash the interpreter).
        vec = self.make(render_mode="rgb_array", render_width=200)
        self.assertRaisesRegex(roger.RogerError, r"render: environment 0 of 3: no world yet \(call reset first\)",
                               vec.render)
        vec.reset(seed=1, options={"reset_mask": np.array([True, False, True])})
        self.assertRaisesRegex(roger.RogerError, "render: environment 1 of 3: no world yet", vec.render)
        vec.reset(options={"reset_mask": np.array([False, True, False])})
        self.assertEqual(len(vec.render()), 3)

    def test_masked_first_reset_plays_distinct_worlds(self):
        # A seeded reset that leaves an environment out gives it its place in the schedule all the
        # same (S + i), so that its first reset does not replay another's worlds; stepping it before
        # any reset is refused, naming it, and nothing runs.
        vec = self.make(2)
        # Before any reset the batch says so plainly (found by a probe: it pointed at reset_mask).
        self.assertRaisesRegex(roger.RogerError, r"^step: no episode is running in the 2 environments \(call reset "
                                                 r"first\)$", vec.step, np.array([0, 0]))
        obs, info = vec.reset(seed=1, options={"reset_mask": np.array([True, False])})
        with self.assertRaises(roger.RogerError) as cm:
            vec.step(np.array([0, 0]))
        self.assertIn("environment 1 of 2 has not been reset yet", str(cm.exception))
        self.assertNotIn("its episode is over", str(cm.exception))
        twin = pickle.loads(pickle.dumps(vec))  # a copy keeps the place too
        for v in (vec, twin):
            _, info = v.reset(options={"reset_mask": np.array([False, True])})
            self.assertEqual(info["seed"][1], 2)
        self.assertEqual(twin.step(np.array([0, 0]))[4]["ticks"][0], vec.step(np.array([0, 0]))[4]["ticks"][0])
        worlds, rng = {0: [1], 1: [2]}, np.random.default_rng(3)
        for _ in range(150):
            _, _, _, _, info = vec.step(rng.integers(0, 2, size=2))
            for i in (0, 1):
                if info["ticks"][i] == 0:  # the first step of an episode (NEXT_STEP autoreset)
                    worlds[i].append(int(info["seed"][i]))
        self.assertGreater(len(worlds[0]) + len(worlds[1]), 10)
        self.assertFalse(set(worlds[0]) & set(worlds[1]), worlds)
        self.assertEqual(worlds[1][:3], [2, 4, 6])

    def test_max_episode_steps_truncates(self):
        # Found by a probe: gymnasium.make_vec(id, n, max_episode_steps=N) hands the keyword to the
        # vector entry point, which raised TypeError. At the N-th decision an episode is truncated
        # (terminated too only when its stage ended it then), and its successor begins as any other's.
        for mode in ("NextStep", "SameStep"):
            with self.subTest(mode=mode):
                vec, free = self.make(2, max_episode_steps=1, autoreset_mode=mode), self.make(2, autoreset_mode=mode)
                vec.reset(seed=4)
                free.reset(seed=4)
                actions = np.array([1, 0])  # phi0 (its time-out ends the episode at once) and search (runs on)
                _, reward, terminated, truncated, info = vec.step(actions)
                _, f_reward, f_terminated, f_truncated, f_info = free.step(actions)
                np.testing.assert_array_equal(reward, f_reward)  # the same decision, only cut short
                np.testing.assert_array_equal(terminated, f_terminated)
                np.testing.assert_array_equal(truncated, [True, True])
                self.assertFalse(f_truncated.any())
                ended = info["final_info"] if mode == "SameStep" else info
                np.testing.assert_array_equal(ended["decisions"], [1, 1])
                self.assertFalse(ended["success"][0])
                _, _, _, _, info = vec.step(actions)
                if mode == "NextStep":  # the next step begins each one's next episode
                    np.testing.assert_array_equal(info["seed"], [6, 7])
                    np.testing.assert_array_equal(info["decisions"], [0, 0])
                copy = pickle.loads(pickle.dumps(vec))  # a copy keeps the cap
                self.assertEqual(copy.step(actions)[3].tolist(), vec.step(actions)[3].tolist())
        for bad in (0, -1, True, 2.5, "3"):
            self.assertRaisesRegex(roger.RogerError, "max_episode_steps must be a positive integer", self.make,
                                   max_episode_steps=bad)

    def test_seeded_reset_keeps_apart_from_those_left_out(self):
        # Found by a probe: a seed given to an environment of a masked reset was checked only
        # against the others reset with it, so seed 11 and the running environment 1's schedule
        # (1, 3, 5, ...) met, and both played 11, 13, 15, ... The highest goes on along its
        # schedule (11, 13, ...); the one left out ends its episode and then continues apart.
        vec = self.make(2)
        vec.reset(seed=0)
        _, info = vec.reset(seed=11, options={"reset_mask": np.array([True, False])})
        self.assertEqual(info["seed"][0], 11)
        later = self.worlds_played(vec, 150)
        worlds = {0: [11] + later[0], 1: [1] + later[1]}
        self.assertGreater(min(len(worlds[0]), len(worlds[1])), 4)
        self.assertFalse(set(worlds[0]) & set(worlds[1]), worlds)
        self.assertEqual(worlds[0][:3], [11, 13, 15])
        self.assertEqual(worlds[1][1], roger.mix(3, 1) >> 1)  # from 3 (its next), the first k of residue 0

    def test_reset_failure_names_the_environment(self):
        # Every episode of this stage ends at once: the reset fails after 1000 of them, and says so
        # as a reset's error of the environment, not as make_vec's.
        vec = roger.make_vec(ABSORBING_AT_ONCE, "Look", "Gaze", num_envs=2, threads=1)
        with self.assertRaises(roger.RogerError) as cm:
            vec.reset(seed=5)
        self.assertEqual(cm.exception.env, 0)
        text = str(cm.exception)
        self.assertTrue(text.startswith("reset: environment 0 of 2 (seed "), text)
        self.assertIn("1000 episodes in a row ended before their first decision (its absorbing function holds at once)",
                      text)
        self.assertNotIn("make_vec", text)

    def test_close_is_final(self):
        vec = self.make()
        vec.reset(seed=1)
        vec.close()
        self.assertTrue(vec.closed)
        self.assertRaisesRegex(roger.RogerError, "closed", vec.step, np.array([0, 0, 0]))
        self.assertRaisesRegex(roger.RogerError, "closed", vec.reset)
        vec.close()

    def test_fault_names_the_environment_and_keeps_the_others(self):
        # timeout_fault's reward fails at a time-out; phi0 alone times out at once here, search not.
        actions = np.array([0, 1, 0])
        vec = roger.make_vec(TIMEOUT_FAULT, "Look", "Gaze", num_envs=3, threads=2)
        vec.reset(seed=100)
        with self.assertRaises(roger.ScriptError) as cm:
            vec.step(actions)
        e = cm.exception
        self.assertEqual(e.env, 1)
        self.assertIn("environment 1 of 3 (seed 101", str(e))
        self.assertEqual((e.file, e.line), (TIMEOUT_FAULT, 10))
        np.testing.assert_array_equal(e.failed, [False, True, False])
        obs, reward, terminated, truncated, info = e.results
        np.testing.assert_array_equal(truncated, [False, True, False])  # the faulted episode is cut short
        single = roger.make(TIMEOUT_FAULT, "Look", "Gaze")
        for i in (0, 2):  # the others stepped, and their outcomes are the single environments'
            single.reset(seed=100 + i)
            s_obs, s_reward, s_term, _, _ = single.step(0)
            np.testing.assert_array_equal(obs[i], s_obs)
            self.assertEqual((reward[i], terminated[i]), (s_reward, s_term))
        try:  # the faulted one begins anew (the others may time out, and fault, in this step)
            results = vec.step(actions)
        except roger.ScriptError as again:
            self.assertFalse(again.failed[1])
            results = again.results
        obs, reward, terminated, truncated, info = results
        self.assertEqual(info["seed"][1], 104)
        self.assertEqual((reward[1], truncated[1]), (0.0, False))


class BadArguments(unittest.TestCase):
    """Bad input raises a Python exception naming the file and the field, never a crash."""

    def assertRaisesWith(self, exc, texts, fn, *args, **kwargs):
        with self.assertRaises(exc) as cm:
            fn(*args, **kwargs)
        for t in texts:
            self.assertIn(t, str(cm.exception))
        return cm.exception

    def test_a_script_of_another_kind_or_an_unknown_member_is_named(self):
        # Found by a probe: a scenario given as the curriculum failed inside scenarios/lib/shapes.lua,
        # a skill script with "unknown field 'policies'", and teacher='roger.teacher.nosuch{}' with
        # "attempt to call a nil value (field 'nosuch')".
        self.assertRaisesWith(roger.RogerError, ["docs/examples/corridor.lua is a scenario, not a curriculum"],
                              roger.make, "docs/examples/corridor.lua", "S", "A")
        self.assertRaisesWith(roger.RogerError, ["scripted is a skill script, not a curriculum"],
                              roger.make, "scripted", "S", "A")
        self.assertRaisesWith(roger.ScriptError, ["make(teacher=...):1: roger.teacher.nosuch is not in the API of a "
                                                  "curriculum; roger.teacher has: alp_gmm, lcas, plr, random, sequence"],
                              roger.make, PAPER, "T", "B2", teacher="roger.teacher.nosuch{}")
        self.assertRaisesWith(roger.ScriptError, ["make(tasks=...):1: roger.intt is not in the API of a curriculum; "
                                                  "did you mean roger.int?"],
                              roger.make, PAPER, "T", "B2", tasks="{obstacles = roger.intt(0, 3)}")

    def test_a_teacher_text_naming_nothing_says_so(self):
        # Found by a probe: teacher="alp_gmm" said "gives no value for 'teacher': write a value", and
        # "alp_gmm{}" "attempt to call a nil value", where a stage's script is told the name is undefined.
        for text in ("alp_gmm", "alp_gmm{}", "alp_gmm{fit_every = 10}"):
            with self.subTest(teacher=text):
                self.assertRaisesWith(roger.ScriptError, [
                    "make(teacher=...):1: undefined global 'alp_gmm'", "a teacher is written roger.teacher.alp_gmm{...}"],
                    roger.make, TEACHERS, "T_alp", "B2", teacher=text)
        self.assertRaisesWith(roger.ScriptError, ["make(tasks=...):1: undefined global 'int'",
                                                  "an axis is written roger.int(...)"],
                              roger.make, PAPER, "T", "B2", tasks="{obstacles = int(0, 3)}")

    def test_a_world_that_cannot_be_placed_names_the_call(self):
        # Found by a probe: make raised the scenario's PlacementError alone, with a Lua traceback
        # and nothing of make, the seed or the parameters given.
        e = self.assertRaisesWith(roger.PlacementError, [
            "make: could not build the world of seed ", "stage 'T', context 'B2'",
            "with the parameters given (robot_distance=99): ", "world:sample_position"],
            roger.make, PAPER, "T", "B2", params={"robot_distance": 99})
        self.assertNotIn("stack traceback", str(e))
        self.assertTrue(e.file.endswith(".lua") and e.line > 0, (e.file, e.line))
        self.assertRaisesWith(roger.PlacementError, ["make_vec: could not build the world of seed ",
                                                     "(robot_distance=99)"],
                              roger.make_vec, PAPER, "T", "B2", 2, params={"robot_distance": 99})
        # A reset's world, and a batch's, which names its environment as for any reset failure.
        self.assertRaisesWith(roger.PlacementError, [
            "reset: could not build the world of seed 0 of stage 'T', context 'B2' with the parameters given "
            "(robot_distance=2.4): "], roger.make(PAPER, "T", "B2", params={"robot_distance": 2.4}).reset, seed=0)
        e = self.assertRaisesWith(roger.PlacementError, [
            "reset: environment 0 of 2 (seed 0): could not build the world of seed 0 of stage 'T', context 'B2' with "
            "the parameters given (robot_distance=2.4): "],
            roger.make_vec(PAPER, "T", "B2", 2, params={"robot_distance": 2.4}).reset, seed=0)
        self.assertEqual(e.env, 0)
        # Found by a probe: a world the parameters make impossible (not a layout a seed misses) was the
        # scenario's error alone, naming neither the call nor the parameter.
        e = self.assertRaisesWith(roger.ScriptError, [
            "could not build the world of seed 1000000 of stage 'Look', context 'Gaze' (its first held-out world, "
            "which gives the body) with the parameters given (goal_x=-1000000000.0): scenarios/lib/place.lua:",
            "centre (-1000000000, 0) is outside the 4 x 4 m arena"],
            roger.make, EXAMPLE, "Look", "Gaze", params={"goal_x": -1e9})
        self.assertNotIsInstance(e, roger.PlacementError)  # no seed holds it: not a task to skip
        self.assertEqual(e.file, "scenarios/lib/place.lua")
        # make's own task space, checked at its ends as roger check checks a stage's: every reset
        # failed with the arena's error.
        e = self.assertRaisesWith(roger.ScriptError, [
            "make(tasks=...):1: stage 'Look': scenario 'unobstructed' with goal_x = -10 (an end of the stage's "
            "task space): scenarios/lib/place.lua:52: world:goal: goal 'goal' centre (-10, 0) is outside",
            "goal_x = 10 (an end"], roger.make, EXAMPLE, "Look", "Gaze", tasks={"goal_x": roger.axis.real(-10, 10)})
        self.assertNotIn("stack traceback", str(e))
        roger.make(EXAMPLE, "Look", "Gaze", tasks={"goal_x": roger.axis.real(-10, 10)}, teacher=False)  # no teacher draws
        env = roger.make(EXAMPLE, "Look", "Gaze", tasks={"robot_distance": roger.axis.real(0.5, 3.5)}, teacher=False)
        self.assertRaisesWith(roger.PlacementError, [
            "reset: could not build the world of seed 1 of stage 'Look', context 'Gaze' with the parameters given "
            "(robot_distance=3.5)"], env.reset, seed=1, options={"task": {"robot_distance": 3.5}})

    def test_axes_are_checked_when_written(self):
        # Found by a probe: reversed or fractional bounds passed until make; the Lua side's words.
        for fn, args, text in (
                (roger.axis.real, (2, 1), "roger.axis.real(2, 1): the range is reversed (lo must be below hi; "
                                          "a single value needs no axis)"),
                (roger.axis.real, (1, 1), "roger.axis.real(1, 1): the range is a single value"),
                (roger.axis.int, (0.5, 3), "roger.axis.int(lo, hi): lo must be an integer, got 0.5"),
                (roger.axis.int, (0, 2.5), "roger.axis.int(lo, hi): hi must be an integer, got 2.5"),
                (roger.axis.int, (3, 1), "roger.axis.int(3, 1): the range is reversed (lo must be below hi; "
                                         "a single value needs no axis)"),
                # Found by a probe: a single value, an empty or a repeated choice passed until make.
                (roger.axis.int, (3, 3), "roger.axis.int(3, 3): the range is a single value (lo must be below hi; "
                                         "a single value needs no axis)"),
                (roger.axis.choice, ([],), "roger.choice{}: the list is empty; a choice is among at least two"),
                (roger.axis.choice, (["circle"],), 'roger.choice{"circle"}: a single value needs no axis'),
                (roger.axis.choice, (["circle", "circle"],), "the value 'circle' is listed twice"),
                (roger.axis.choice, ([1, "1"],), "the value '1' is listed twice")):
            with self.subTest(args=args):
                self.assertRaisesWith(roger.RogerError, [text], fn, *args)
        self.assertEqual(repr(roger.axis.int(2.0, 3)), "roger.int(2.0, 3)")
        self.assertEqual(repr(roger.axis.choice(["circle", 2, True])), 'roger.choice{"circle", 2, true}')
        self.assertEqual(repr(roger.axis.real(0.5, 2)), "roger.real(0.5, 2)")

    def test_unknown_stage_and_context(self):
        self.assertRaisesWith(roger.RogerError, ["Nope", "Look"], roger.make, EXAMPLE, "Nope", "Gaze")
        # The file is named for an unknown context as for an unknown stage.
        self.assertRaisesWith(roger.RogerError, [EXAMPLE + ": stage 'Look' has no context 'Nope'", "Gaze"], roger.make,
                              EXAMPLE, "Look", "Nope")
        self.assertRaisesWith(roger.RogerError, [EXAMPLE + ": stage 'Look' has no context 'Nope'"], roger.make_vec,
                              EXAMPLE, "Look", "Nope", 2)
        self.assertRaisesWith(roger.RogerError, ["no_such_curriculum"], roger.make, "no_such_curriculum", "T", "B2")
        # Found by a probe: "curricula/.lua does not exist", the folder's name as a missing script,
        # a scenario's name with no word of it, and the stage and context swapped said only the first.
        self.assertRaisesWith(roger.RogerError, ["no curriculum given: the name is empty"], roger.make, "", "T", "B2")
        folder = os.path.dirname(os.path.abspath(PAPER))
        self.assertRaisesWith(roger.RogerError, [f"'{folder}' is a folder: give one script in it"],
                              roger.make, folder, "T", "B2")
        self.assertRaisesWith(roger.RogerError, ["no curriculum 'unobstructed'",
                                                 "scenarios/unobstructed.lua is a scenario, another kind of script"],
                              roger.make, "unobstructed", "T", "B2")
        self.assertRaisesWith(roger.RogerError, ["has no stage 'DC6' ('DC6' is a context of stage 'T': a stage comes "
                                                 "first, then its context); its stages: SG, T"],
                              roger.make, PAPER, "DC6", "T")
        self.assertRaisesWith(roger.RogerError, [os.path.join(WORK, "none.json") + ": no such file"],
                              roger.load_policy, os.path.join(WORK, "none.json"))
        self.assertRaisesWith(roger.RogerError, ["shape"], roger.make, PAPER, "T", "B2", params={"shape": "cube"})

    def test_missing_learned_skill(self):
        self.assertRaisesWith(roger.RogerError, ["Phi_SG", "skills="], roger.make, PAPER, "T", "DC6")

    def test_unused_skill_is_refused(self):
        # As roger train refuses a --skill the context does not use: a misspelt name is not ignored.
        self.assertRaisesWith(roger.RogerError, ["make: skills={'Phi_XX': 'x.json'}", PAPER, "stage 'T', context 'B2'",
                                                 "uses no learned skill 'Phi_XX' (it uses none)"],
                              roger.make, PAPER, "T", "B2", skills={"Phi_XX": "x.json"})
        self.assertRaisesWith(roger.RogerError, ["uses no learned skill 'Phi_XX'; it uses Phi_SG"],
                              roger.make, PAPER, "T", "DC6", skills={"Phi_SG": "sg.json", "Phi_XX": "x.json"})
        self.assertRaisesWith(roger.RogerError, ["make_vec: skills={'Phi_XX': 'x.json'}"],
                              roger.make_vec, PAPER, "T", "B2", 2, skills={"Phi_XX": "x.json"})

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

    def test_batch_seeds_and_actions_as_given(self):
        # Found by a probe: a 0-d array as a batch's seed raised "TypeError: len() of unsized
        # object"; a uint64 action past 2^63 - 1 was named -1.
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=2, threads=1)
        for bad in (np.array(5), np.array([[1, 2]])):
            with self.subTest(seed=bad):
                self.assertRaisesWith(roger.RogerError, ["reset: a seed is an integer in [0, 2^64)", repr(bad)],
                                      vec.reset, seed=bad)
        vec.reset(seed=np.array([5, 6]))  # a 1-D array is a list of seeds
        self.assertRaisesWith(roger.RogerError, ["action 18446744073709551615 of environment 0 is not in [0, 2)"],
                              vec.step, np.array([2 ** 64 - 1, 0], dtype=np.uint64))
        vec.step(np.array([1, 0], dtype=np.uint64))  # in range, any integer dtype

    def test_make_vec_counts_are_integers(self):
        # Found by a probe: threads=1.7 ran 1 thread, "2" and True were taken; refused as num_envs is.
        for name in ("threads", "num_envs"):
            for bad in (1.7, "2", True, 0, -1, 0.5):
                with self.subTest(name=name, value=bad):
                    args = {"num_envs": 2, name: bad}
                    self.assertRaisesWith(roger.RogerError, [f"make_vec: {name} must be a positive integer, "
                                                             f"got {bad!r}"],
                                          roger.make_vec, EXAMPLE, "Look", "Gaze", **args)
        self.assertEqual(roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=2, threads=np.int64(2)).threads, 2)

    def test_make_vec_counts_are_bounded(self):
        # Found by a probe: num_envs=2**40, threads=2**40 and max_episode_steps=10**30 raised pybind11's
        # TypeError with its signature, and num_envs=2**31 - 1 was taken and allocated until
        # std::bad_alloc. Each is checked against its bound first, named with it and the value.
        for name, bound, bad in (("num_envs", 4096, 4097), ("num_envs", 4096, 2**40), ("threads", 1024, 1025),
                                 ("threads", 1024, 2**40), ("max_episode_steps", 2**31 - 1, 2**31),
                                 ("max_episode_steps", 2**31 - 1, 10**30), ("num_envs", 4096, 2**31 - 1)):
            with self.subTest(name=name, value=bad):
                args = {"num_envs": 2, name: bad}
                self.assertRaisesWith(roger.RogerError, [f"make_vec: {name} is at most {bound} (", f"got {bad}"],
                                      roger.make_vec, EXAMPLE, "Look", "Gaze", **args)
        self.assertRaisesWith(roger.RogerError, ["make_vec: num_envs is at most 4096", "an integer of 4001 bits"],
                              roger.make_vec, EXAMPLE, "Look", "Gaze", num_envs=2**4000)
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=2, threads=1024, max_episode_steps=2**31 - 1)
        self.assertEqual(vec.threads, 2)  # more threads than environments run as many as them
        vec.reset(seed=1)
        vec.step(np.zeros(2, int))

    def test_arguments_of_the_wrong_kind_are_named(self):
        # Found by a probe: make(..., policy=5) said "5: cannot read the policy file", load_policy(None)
        # "None: ...", params={"robot_distance": None} "got 'None'" (str(None) was taken as the text),
        # roger.axis.choice([None, 1]) "a bound is a finite number", and a policy of 2 actions given
        # one value "the observation has 1 values".
        self.assertRaisesWith(roger.RogerError, ["make: policy is the path of a policy.json (a str or os.PathLike) "
                                                 "or a roger.Policy, got int 5"],
                              roger.make, EXAMPLE, "Look", "Gaze", policy=5)
        self.assertRaisesWith(roger.RogerError, ["make_vec: policy is the path", "got list [1]"],
                              roger.make_vec, EXAMPLE, "Look", "Gaze", num_envs=2, policy=[1])
        for bad in (None, 5):
            self.assertRaisesWith(roger.RogerError, ["load_policy: expected the path of a policy.json (a str or "
                                                     f"os.PathLike), got {type(bad).__name__} {bad!r}"],
                                  roger.load_policy, bad)
        self.assertRaisesWith(roger.RogerError, ["params['robot_distance'] is None, which is no value: give a number, "
                                                 "a string or a bool"],
                              roger.make, EXAMPLE, "Look", "Gaze", params={"robot_distance": None})
        self.assertRaisesWith(roger.RogerError, ["params['robot_distance'] is None"], roger.make_vec, EXAMPLE, "Look",
                              "Gaze", num_envs=2, params={"robot_distance": None})
        self.assertRaisesWith(roger.RogerError, ["skills['Phi_SG'] is None", "the path of a policy.json"],
                              roger.make, PAPER, "T", "DC6", skills={"Phi_SG": None})
        for bad, shown in ((None, "NoneType None"), ([1], "list [1]")):
            self.assertRaisesWith(roger.RogerError, ["roger.axis.choice: a value is a string, a finite number or a "
                                                     f"bool, got {shown}"], roger.axis.choice, [bad, 1])
        self.assertRaisesWith(roger.RogerError, ["roger.axis.choice: a value is a finite number, got inf"],
                              roger.axis.choice, [float("inf"), 1])
        self.assertRaisesWith(roger.RogerError, ["roger.axis.int: a bound is a finite number"], roger.axis.int, None, 3)
        policy = roger.load_policy(train(EXAMPLE, "Look", "Gaze", 3, "look"))
        e = self.assertRaisesWith(roger.RogerError, ["the policy has 2 actions but the observation has 1 value"],
                                  policy.act, [1])
        self.assertNotIn("1 values", str(e))
        self.assertRaisesWith(roger.RogerError, ["the observation has 3 values"], policy.act, [1, 1, 1])
        # Found by a probe: a curriculum given as the scenario failed inside it ("skills.lua:45: attempt
        # to call a nil value"); it is named as what it is, as on the command line.
        self.assertRaisesWith(roger.RogerError, ["scenario= curricula/paper.lua is a curriculum, not a scenario"],
                              roger.make, EXAMPLE, "Look", "Gaze", scenario=PAPER)

    def test_every_batch_action_is_checked(self):
        # Found by a probe: on a NEXT_STEP autoreset step an out-of-range action of an environment
        # beginning its next episode was accepted silently, while the same action elsewhere was
        # refused; every action is checked on every step.
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=3, threads=2)
        vec.reset(seed=1)
        rng = np.random.default_rng(2)
        for _ in range(2000):
            _, _, terminated, truncated, _ = vec.step(rng.integers(0, 2, size=3))
            ended = np.flatnonzero(terminated | truncated)
            if ended.size:
                break
        self.assertTrue(ended.size, "no episode ended")
        i = int(ended[0])
        for bad in (99, -1):
            actions = np.zeros(3, int)
            actions[i] = bad
            self.assertRaisesWith(roger.RogerError, [f"action {bad} of environment {i} is not in [0, 2)"],
                                  vec.step, actions)
        # Found by a probe: a bool among the indices read as 1 or 0.
        self.assertRaisesWith(roger.RogerError, ["step: expected 3 integer actions, got a list holding a bool: "
                                                 "[True, 0, 1]"], vec.step, [True, 0, 1])
        _, _, terminated, truncated, _ = vec.step(np.zeros(3, int))  # the refused steps ran nothing
        self.assertFalse(terminated[i] or truncated[i])

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

    def test_policy_of_other_actions_and_undecodable_input(self):
        # Found by a probe: a policy whose actions were another order (or names) than the
        # environment's was taken, and played other actions than it chose (20 of 20 fell to 6);
        # roger eval refuses it, and so do make, make_vec and Policy.make.
        path = train(EXAMPLE, "Look", "Gaze", 3, "look")
        with open(EXAMPLE) as f:
            text = f.read()
        self.assertIn("actions = { p.search, p.phi0 }", text)
        swapped = os.path.join(WORK, "swapped.lua")
        with open(swapped, "w") as f:
            f.write(text.replace("actions = { p.search, p.phi0 }", "actions = { p.phi0, p.search }"))
        policy = roger.load_policy(path)
        said = ['field "actions" is ["search", "phi0"] but this stage\'s actions are ["phi0", "search"]',
                "a policy is tied to its action set and order"]
        self.assertRaisesWith(roger.RogerError, ["make: "] + said, policy.make, curriculum=swapped)
        self.assertRaisesWith(roger.RogerError, ["make: "] + said, roger.make, swapped, "Look", "Gaze", policy=path)
        self.assertRaisesWith(roger.RogerError, ["make_vec: "] + said, roger.make_vec, swapped, "Look", "Gaze", 2,
                              policy=policy)
        # A file that is not UTF-8 is named with its parse error (the message was empty).
        bad = os.path.join(WORK, "not_utf8.json")
        with open(bad, "wb") as f:
            f.write(b"\xc3\x28{}")
        e = self.assertRaisesWith(roger.RogerError, ["not_utf8.json", "parse error", "\\xC3"], roger.load_policy, bad)
        self.assertTrue(str(e))
        # File names and values that are not UTF-8 are the bytes the command line passes (they
        # raised a binding's TypeError or RuntimeError).
        odd = os.path.join(os.fsencode(WORK), b"cur\xff.lua")
        shutil.copy(EXAMPLE, odd)
        env = roger.make(os.fsdecode(odd), "Look", "Gaze")
        env.reset(seed=1)
        self.assertEqual(os.path.basename(os.fsencode(env.stage_info["curriculum"])), b"cur\xff.lua")
        odd_policy = os.path.join(os.fsencode(WORK), b"pol\xff.json")
        shutil.copy(path, odd_policy)
        self.assertEqual(roger.load_policy(os.fsdecode(odd_policy)).actions, ("search", "phi0"))
        self.assertRaisesWith(roger.RogerError, ["parameter 'shape'", "got 'caf\\xE9'"], roger.make, PAPER, "T", "B2",
                              params={"shape": os.fsdecode(b"caf\xe9")})

    def test_policy_make_names_the_recorded_curriculum(self):
        # Found by a probe: a policy trained with a relative curriculum path, made from another
        # folder, said only "no curriculum 'mycur.lua'".
        folder = os.path.join(WORK, "own_project")
        os.makedirs(folder, exist_ok=True)
        shutil.copy(EXAMPLE, os.path.join(folder, "mycur.lua"))
        out = os.path.join(folder, "out")
        if not os.path.exists(os.path.join(out, "policy.json")):
            subprocess.run([ROGER, "train", "mycur.lua", "--stage", "Look", "--context", "Gaze", "--seed", "2",
                            "--out", "out"], cwd=folder, check=True, capture_output=True)
        policy = roger.load_policy(os.path.join(out, "policy.json"))
        self.assertEqual(policy.curriculum, "mycur.lua")
        self.assertRaisesWith(roger.RogerError, ["records the curriculum 'mycur.lua' as roger train was given it",
                                                 "no curriculum 'mycur.lua'", "policy.make(curriculum="], policy.make)
        self.assertEqual(policy.make(curriculum=os.path.join(folder, "mycur.lua")).actions, ("search", "phi0"))

    def test_a_policy_played_in_a_changed_or_other_curriculum_is_warned_of(self):
        # Found by a probe: policy.make() played the project's copy of the curriculum the trial's
        # folder had an edited copy of, and a curriculum edited since, without a word (roger eval
        # notes both).
        import warnings
        folder = os.path.join(WORK, "edited_project", "docs", "examples")
        os.makedirs(folder, exist_ok=True)
        with open(EXAMPLE) as f:
            text = f.read().replace("time_limit = 4,", "time_limit = 7,")
        with open(os.path.join(folder, "curriculum_example.lua"), "w") as f:
            f.write(text)
        root = os.path.join(WORK, "edited_project")
        out = os.path.join(root, "out")
        if not os.path.exists(os.path.join(out, "policy.json")):
            subprocess.run([ROGER, "train", EXAMPLE, "--stage", "Look", "--context", "Gaze", "--seed", "2",
                            "--out", "out"], cwd=root, check=True, capture_output=True)
        policy = roger.load_policy(os.path.join(out, "policy.json"))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            env = policy.make()  # from here: the project's own copy, which the trial did not train with
        self.assertEqual(env.stage_info["time_limit"], 4.0)
        said = [str(w.message) for w in caught if issubclass(w.category, roger.RogerWarning)]
        self.assertEqual(len(said), 1, said)
        self.assertIn(f"the curriculum {EXAMPLE} changed since the policy was trained; stage Look, context Gaze",
                      said[0])
        self.assertEqual(caught[0].filename, __file__)  # the user's line
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            env = roger.make(os.path.join(folder, "curriculum_example.lua"), "Look", "Gaze", policy=policy)
        self.assertEqual([w for w in caught if issubclass(w.category, roger.RogerWarning)], [])
        self.assertEqual(env.stage_info["time_limit"], 7.0)

    def test_state_index_overflow(self):
        self.assertEqual(roger.state_index([2] * 19), 3 ** 19 - 1)
        self.assertRaisesWith(roger.RogerError, ["20 actions", "at most 19"], roger.state_index, [2] * 20)

    def test_state_index_takes_what_act_takes(self):
        # The integers 0, 1, 2 (whole floats too), as Policy.act; fractions and booleans are refused
        # with a RogerError, never a binding's TypeError or a boolean read as a number.
        self.assertEqual(roger.state_index([2, 1]), 7)
        self.assertEqual(roger.state_index(np.array([2.0, 1.0])), 7)
        self.assertEqual(roger.state_index(np.array([2, 1], np.uint8)), 7)
        # [True, 1, 0] is an int64 array to numpy, the boolean read as 1 (found by a probe).
        for bad, text in (([1.5, 0], "integers 0 (NOREF)"), ([True, False], "integers 0 (NOREF)"),
                          ([True, 1, 0], "integers 0 (NOREF)"), ((1, np.True_), "integers 0 (NOREF)"),
                          (["a", "b"], "integers 0 (NOREF)"), ([0, 3], "is 0, 1 or 2, got 3"),
                          ([0, 10 ** 12], "is 0, 1 or 2")):
            with self.subTest(bad=bad):
                self.assertRaisesWith(roger.RogerError, [text], roger.state_index, bad)

    def test_a_tick_observation_given_as_a_state(self):
        # Found by a probe: policy.act and state_index given a tick mode observation (a dict) put
        # its whole image array in an error of 8000 characters; a line says to pass obs["state"].
        policy = roger.load_policy(train(EXAMPLE, "Look", "Gaze", 3, "look"))
        obs, _ = policy.make(mode="tick").reset(seed=1)
        for fn, where in ((policy.act, "act"), (roger.state_index, "state_index")):
            with self.subTest(where):
                e = self.assertRaisesWith(roger.RogerError, [f"{where}: takes ", "got a dict", "tick mode observation",
                                                             "obs['state']"], fn, obs)
                self.assertLess(len(str(e)), 300, str(e))
        self.assertEqual(policy.act(obs["state"]), policy.act(list(obs["state"])))
        e = self.assertRaisesWith(roger.RogerError, ["integers 0 (NOREF)"], policy.act, np.full((2, 4000), 0.5))
        self.assertLess(len(str(e)), 300)  # any other value is shown cut short too

    def test_empty_state_and_names_that_are_not_text(self):
        # Found by a probe: state_index([]) was 0, and make(..., None, ...) looked for a stage 'None'.
        self.assertRaisesWith(roger.RogerError, ["state_index", "got an empty vector"], roger.state_index, [])
        for make, where, args in ((roger.make, "make", ()), (roger.make_vec, "make_vec", (2,))):
            with self.subTest(where):
                self.assertRaisesWith(roger.RogerError, [f"{where}: stage must be a str", "got NoneType None"], make,
                                      PAPER, None, "B2", *args)
                self.assertRaisesWith(roger.RogerError, [f"{where}: context must be a str", "got int 2"], make,
                                      PAPER, "T", 2, *args)
                self.assertRaisesWith(roger.RogerError, [f"{where}: curriculum must be a path", "got NoneType"], make,
                                      None, "T", "B2", *args)

    def test_mix_takes_the_engines_tags(self):
        # docs/python.md writes the teacher's stream as roger.mix(S, "teach"), the engine's tag.
        self.assertEqual(roger.mix(5, "teach"), roger.mix(5, 0x7465616368))
        env = roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS)
        env.reset(seed=9)
        self.assertEqual(env._teacher_seed, roger.mix(9, "teach"))
        for bad in ("", "too long a tag", -1):
            with self.subTest(bad=bad):
                self.assertRaises(roger.RogerError, roger.mix, 5, bad)
        self.assertRaises(roger.RogerError, roger.mix, -5, 1)

    def test_closed_environment_refuses_every_method(self):
        # close() is final (docs/python.md): the task and teacher methods raise too; what describes
        # the environment stays readable.
        env = roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS)
        env.reset(seed=1)
        env.close()
        for name, call in (("set_task", lambda: env.set_task(None)), ("get_task", env.get_task),
                           ("sample_tasks", lambda: env.sample_tasks(1)), ("task_params", lambda: env.task_params({})),
                           ("teacher_state", lambda: env.teacher_state), ("render", env.render)):
            with self.subTest(name):
                self.assertRaisesWith(roger.RogerError, [name, "closed"], call)
        self.assertEqual((env.actions, env.stage_info["stage"]), (("search", "phi0"), "Look"))
        self.assertIsNotNone(env.task_space)

    def test_policy_act_refuses_fractions(self):
        policy = roger.load_policy(train(EXAMPLE, "Look", "Gaze", 3, "look"))
        self.assertEqual(policy.act([2.0, 1.0]), policy.act([2, 1]))  # whole floats are the integers
        self.assertRaisesWith(roger.RogerError, ["integers 0 (NOREF)"], policy.act, [1.9, 0.7])
        self.assertRaisesWith(roger.RogerError, ["integers 0 (NOREF)"], policy.act, ["a", "b"])
        self.assertRaisesWith(roger.RogerError, ["integers 0 (NOREF)"], policy.act, [True, 1])
        # Found by a probe: a batch was refused as "2 actions but the observation has 4 values".
        self.assertRaisesWith(roger.RogerError, ["takes one observation", "not a batch", "shape (2, 2)",
                                                 "[policy.act(o) for o in obs]"], policy.act, np.array([[0, 0], [1, 1]]))

    def test_bad_seeds_raise_roger_error(self):
        # Checked before gymnasium's own seeding sees them, so the error is ours with or without it.
        env = roger.make(EXAMPLE, "Look", "Gaze")
        for bad in (-1, 2 ** 64, 1.5, "7", True):
            with self.subTest(seed=bad):
                self.assertRaisesWith(roger.RogerError, ["seed"], env.reset, seed=bad)
        self.assertRaisesWith(roger.RogerError, ["options"], env.reset, seed=1, options=[1])

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
        # The episode is over, ended by the fault (not by terminated or truncated, as a probe found
        # it said).
        self.assertRaisesWith(roger.RogerError, ["an error ended it", "not terminated or truncated", "call reset"],
                              env.step, 0)
        env.reset(seed=2)  # and the environment usable again


def gymnasium_style(make_env, n, seed, steps, rng_seed=7):
    """What Gymnasium's SyncVectorEnv and Stable-Baselines3's DummyVecEnv do with single
    environments: environment i reset with seed S + i, then each ended episode's successor begun
    by an unseeded reset (at the environment's next step, Gymnasium's NEXT_STEP), random actions.
    Returns the world seed of every episode begun."""
    envs = [make_env() for _ in range(n)]
    rng = np.random.default_rng(rng_seed)
    seeds, pending = [], [False] * n
    for i, env in enumerate(envs):
        seeds.append(env.reset(seed=seed + i)[1]["seed"])
    for _ in range(steps):
        for i, env in enumerate(envs):
            if pending[i]:
                seeds.append(env.reset()[1]["seed"])
                pending[i] = False
            else:
                _, _, terminated, truncated, _ = env.step(int(rng.integers(env.action_space.n)))
                pending[i] = terminated or truncated
    return seeds


def assert_same_step(test, a, b, where):
    """Two step (or reset) results equal, observations (dicts in tick mode) and info included."""
    test.assertEqual(len(a), len(b), where)
    for x, y in zip(a, b):
        if isinstance(x, dict):
            test.assertEqual(sorted(x), sorted(y), where)
            for k in x:
                assert_same_step(test, (x[k],), (y[k],), f"{where}: {k}")
        elif isinstance(x, np.ndarray) and x.dtype == object:
            test.assertEqual([None if v is None else v.tolist() for v in x],
                             [None if v is None else v.tolist() for v in y], where)
        else:
            np.testing.assert_array_equal(x, y, where)


class DeepRL(unittest.TestCase):
    """What a deep-RL library needs of the environments, without gymnasium or Stable-Baselines3:
    distinct worlds under Gymnasium-style vectorization, the vector entry point, copies that
    continue, is_success, tick observations in their spaces, the time-out as a truncation, and
    reset options that are refused when unknown."""

    def test_gymnasium_style_vectorization_plays_distinct_worlds(self):
        # Seeded S + i and then reset without a seed, environment 1 used to replay environment 0's
        # worlds one episode behind (26% distinct): each now follows its own stream.
        seeds = gymnasium_style(lambda: roger.make(EXAMPLE, "Look", "Gaze"), 4, 500, 400)
        print(f"{len(seeds)} episodes in {len(set(seeds))} distinct worlds")
        self.assertGreater(len(seeds), 150)  # many episodes (random actions end one in ~9 steps)
        self.assertEqual(len(set(seeds)), len(seeds))

    def test_unseeded_resets_follow_the_last_seed(self):
        env = roger.make(EXAMPLE, "Look", "Gaze")
        self.assertEqual(env.reset(seed=123)[1]["seed"], 123)
        worlds = [env.reset()[1]["seed"] for _ in range(3)]
        self.assertEqual(worlds, [roger.mix(123, k) >> 1 for k in (1, 2, 3)])
        env.reset(seed=123)  # a seeded reset starts the stream again
        self.assertEqual(env.reset()[1]["seed"], worlds[0])
        # Never seeded: the stream's seed comes from the operating system, as Gymnasium's
        # generators do, and the world it played is in info (reset(seed=...) plays it again).
        a, b = roger.make(EXAMPLE, "Look", "Gaze"), roger.make(EXAMPLE, "Look", "Gaze")
        (obs_a, info_a), (_, info_b) = a.reset(), b.reset()
        self.assertNotEqual(info_a["seed"], info_b["seed"])
        np.testing.assert_array_equal(b.reset(seed=info_a["seed"])[0], obs_a)
        self.assertEqual(a.reset()[1]["seed"], roger.mix(info_a["seed"], 1) >> 1)
        # Below 2^63: Gymnasium's vector environments gather info["seed"] in int64 arrays.
        self.assertLess(max(worlds + [info_a["seed"], info_b["seed"]]), 2 ** 63)

    def test_vector_entry_point(self):
        # gymnasium.make_vec(id, num_envs, vectorization_mode="vector_entry_point") calls make_vec
        # with keywords only, the id's arguments among them (mode too, when the user gives it).
        vec = roger.make_vec(num_envs=3, curriculum=EXAMPLE, stage="Look", context="Gaze", mode="decision",
                             render_mode=None)
        self.assertIsInstance(vec, roger.VecEnv)
        self.assertEqual((vec.num_envs, vec.actions), (3, ("search", "phi0")))
        self.assertRaisesRegex(roger.RogerError, "vectorization_mode='sync'", roger.make_vec, EXAMPLE, "Look",
                               "Gaze", 2, mode="tick")

    def check_copies_continue(self, env, actions, where, first_seed=None):
        """Copies of env (pickle, deepcopy) are where env is: the same picture, and the same
        steps, resets and np_random afterwards (after reset(seed=first_seed) of each, if given:
        a stream never seeded is drawn at the first reset, by each copy for itself)."""
        copies = [pickle.loads(pickle.dumps(env)), copy.deepcopy(env)]
        for c in copies:
            self.assertIsNot(c._env, env._env)
            if env.render_mode and env._env.begun:
                np.testing.assert_array_equal(c.render(), env.render(), where)
        if first_seed is not None:
            resets = [e.reset(seed=first_seed) for e in [env] + copies]
            for r in resets[1:]:
                assert_same_step(self, resets[0], r, f"{where}, first reset")
        rng = np.random.default_rng(11)
        for k in range(actions):
            a = int(rng.integers(env.action_space.n))
            results = []
            for e in [env] + copies:
                if e._env.running:
                    results.append(e.step(a))
                else:  # ended: the next world of each one's stream
                    results.append(e.reset())
            for r in results[1:]:
                assert_same_step(self, results[0], r, f"{where}, step {k}")
        draws = [e.np_random.integers(1 << 30, size=3) for e in [env] + copies]
        for d in draws[1:]:
            np.testing.assert_array_equal(draws[0], d, where)

    def test_copies_continue_the_episode(self):
        for mode, steps in (("decision", 1), ("tick", 40)):
            env = roger.make(EXAMPLE, "Look", "Gaze", mode=mode, render_mode="rgb_array", render_width=200)
            self.check_copies_continue(env, 5, f"{mode}, before any reset", first_seed=7)
            env.reset(seed=41)
            for _ in range(steps):  # searching: the ball comes into view, the episode runs on
                self.assertFalse(env.step(0)[2])
            self.check_copies_continue(env, 60, f"{mode}, mid-episode")
        # An ended episode is ended in the copy too; a closed environment's copy is closed.
        env = roger.make(EXAMPLE, "Look", "Gaze")
        env.reset(seed=3)
        while not env.step(0)[2]:
            pass
        twin = copy.deepcopy(env)
        self.assertRaisesRegex(roger.RogerError, "call reset", twin.step, 0)
        self.assertEqual(twin.reset()[1]["seed"], env.reset()[1]["seed"])
        env.close()
        self.assertRaisesRegex(roger.RogerError, "closed", pickle.loads(pickle.dumps(env)).reset)

    def test_copies_from_another_working_directory(self):
        # Found by a probe: a copy re-made the environment with the relative paths as typed, so a
        # copy made after os.chdir (a SubprocVecEnv's worker elsewhere) found no curriculum.
        here = os.getcwd()
        folder = os.path.join(WORK, "elsewhere")
        os.makedirs(os.path.join(folder, "cur"), exist_ok=True)
        shutil.copy(EXAMPLE, os.path.join(folder, "cur", "example.lua"))
        policy = os.path.abspath(train(EXAMPLE, "Look", "Gaze", 3, "look"))
        shutil.copy(policy, os.path.join(folder, "cur", "policy.json"))
        try:
            os.chdir(folder)
            env = roger.make("cur/example.lua", "Look", "Gaze", policy="cur/policy.json")
            env.reset(seed=5)
            env.step(0)
            bare = roger.make("paper", "T", "B2")  # a bare name is the project's, from anywhere
            os.chdir(tempfile.gettempdir())
            for twin in (copy.deepcopy(env), pickle.loads(pickle.dumps(env))):
                self.assertEqual(twin.stage_info["curriculum"], env.stage_info["curriculum"])  # as typed
                np.testing.assert_array_equal(twin.step(1)[0], copy.deepcopy(env).step(1)[0])
            self.assertEqual(copy.deepcopy(bare).stage_info["curriculum"], bare.stage_info["curriculum"])
            if roger.spaces.__name__.startswith("gymnasium"):
                self.assertEqual(copy.deepcopy(env).spec.kwargs["curriculum"], "cur/example.lua")
            data = pickle.dumps(env)
            os.remove(os.path.join(folder, "cur", "example.lua"))
            with self.assertRaises(roger.RogerError) as cm:  # re-creating the copy fails: it says so
                pickle.loads(data)
            for text in ("copy: could not re-create the copy of <roger.Env", "stage Look context Gaze",
                         "example.lua"):
                self.assertIn(text, str(cm.exception))
        finally:
            os.chdir(here)

    def test_paths_as_pathlib(self):
        # Found by a probe: a pathlib.Path was taken for the curriculum but a copy made after
        # os.chdir lost it (only text was made absolute), the spec could not be written as JSON,
        # scenario=Path raised pybind11's TypeError and teacher=Path was refused.
        import pathlib
        here = os.getcwd()
        teacher = os.path.join(WORK, "path_teacher.lua")
        with open(teacher, "w") as f:
            f.write('return roger.teacher.random{}\n')
        env = roger.make(pathlib.Path(EXAMPLE), "Look", "Gaze", scenario=pathlib.Path("scenarios/unobstructed.lua"),
                         tasks=LOOK_TASKS, teacher=pathlib.Path(teacher))
        vec = roger.make_vec(pathlib.Path(EXAMPLE), "Look", "Gaze", 2, scenario=pathlib.Path("scenarios/unobstructed.lua"))
        env.reset(seed=3)
        vec.reset(seed=3)
        try:
            os.chdir(tempfile.gettempdir())
            for original in (env, vec):
                twin = copy.deepcopy(original)
                self.assertEqual(repr(twin), repr(original))
            np.testing.assert_array_equal(copy.deepcopy(env).step(0)[0], copy.deepcopy(env).step(0)[0])
        finally:
            os.chdir(here)
        if roger.spaces.__name__.startswith("gymnasium"):
            self.assertIn('"curriculum": "docs/examples/curriculum_example.lua"', env.spec.to_json())

    def test_close_from_another_thread_waits_for_the_step(self):
        # Found by a probe: close() from another thread while step() ran in C++ left the step to
        # read a closed environment (AttributeError); close waits for the step to end.
        env = roger.make(PAPER, "T", "B2")
        env.reset(seed=1)
        stepped, errors = threading.Event(), []

        def run():
            try:
                for i in range(100000):
                    _, _, terminated, truncated, _ = env.step(i % len(env.actions))
                    stepped.set()
                    if terminated or truncated:
                        env.reset()
            except roger.RogerError as e:
                errors.append(e)
            except Exception as e:  # what the probe met
                errors.append(e)
        thread = threading.Thread(target=run)
        thread.start()
        self.assertTrue(stepped.wait(60))
        env.close()
        thread.join(60)
        self.assertEqual(len(errors), 1, errors)
        self.assertIsInstance(errors[0], roger.RogerError)
        self.assertIn("the environment is closed", str(errors[0]))

    def test_one_environment_in_two_threads_is_refused(self):
        # Found by a probe: two threads stepping one environment got misleading errors ("the last
        # reset was refused"); using it from a second thread meanwhile is refused, saying so.
        env = roger.make(PAPER, "T", "B2")
        env.reset(seed=1)
        errors, stop = [], threading.Event()

        def run(k):
            try:
                i = 0
                while not stop.is_set():
                    i += 1
                    _, _, terminated, truncated, _ = env.step((i + k) % len(env.actions))
                    if terminated or truncated:
                        env.reset()
            except roger.RogerError as e:
                errors.append(e)
                stop.set()
        threads = [threading.Thread(target=run, args=(k,)) for k in range(2)]
        for t in threads:
            t.start()
        stop.wait(120)
        stop.set()
        for t in threads:
            t.join(60)
        self.assertTrue(errors)
        for text in ("is being used by another thread at the same time",
                     "one environment is not shared between threads", "make one environment per thread"):
            self.assertIn(text, str(errors[0]))
        env.reset(seed=1)  # one thread at a time is fine
        env.close()

    def test_one_batch_in_several_threads_is_refused(self):
        # Found by a probe: three threads stepping one make_vec batch aborted the interpreter
        # (b2StackAllocator's assertion, malloc's corruption) or hung it. Any call of another
        # thread while one runs is refused as for Env, and close waits. Run in a child process
        # with a time limit, so that a crash or a hang fails this test rather than the suite.
        child = textwrap.dedent("""
            import pickle, sys, threading
            import numpy as np
            import roger
            vec = roger.make_vec(sys.argv[1], "T", "B2", 16, threads=2, render_mode="rgb_array",
                                 render_width=100)
            vec.reset(seed=0)
            errors, other = [], []
            calls = [lambda: vec.step(np.zeros(16, int)), lambda: vec.reset(), lambda: pickle.dumps(vec),
                     lambda: vec.render()]
            def run(k):
                for i in range(30):
                    try:
                        calls[(i + k) % len(calls)]()
                    except roger.RogerError as e:
                        errors.append(str(e))
                    except Exception as e:
                        other.append(repr(e))
            threads = [threading.Thread(target=run, args=(k,)) for k in range(3)]
            for t in threads:
                t.start()
            for t in threads:
                t.join()
            vec.reset(seed=0)  # one thread at a time is fine
            # close() from another thread while a step runs waits for it; the next call meets it closed.
            stepping, closed_errors = threading.Event(), []
            def steps():
                try:
                    while True:
                        vec.step(np.zeros(16, int))
                        stepping.set()
                except roger.RogerError as e:
                    closed_errors.append(str(e))
            t = threading.Thread(target=steps)
            t.start()
            stepping.wait(60)
            vec.close()
            t.join(60)
            print(repr((errors, other, closed_errors)))
            """)
        try:
            out = subprocess.run([sys.executable, "-c", child, PAPER], capture_output=True, text=True, timeout=240)
        except subprocess.TimeoutExpired:
            self.fail("one batch used from three threads hung")
        self.assertEqual(out.returncode, 0, out.stderr[-3000:])
        errors, other, closed_errors = eval(out.stdout.strip().splitlines()[-1])
        self.assertEqual(other, [])
        self.assertTrue(errors, "no call met another's: the test did not exercise the guard")
        for e in errors:
            for text in ("is being used by another thread at the same time", "one make_vec batch is not shared "
                         "between threads"):
                self.assertIn(text, e)
        self.assertEqual(len(closed_errors), 1, closed_errors)
        self.assertIn("the vector environment is closed", closed_errors[0])

    def test_a_batch_in_a_forked_child_is_refused(self):
        # Found by a probe: a make_vec batch of 2 threads used in a fork()ed child hung forever (its
        # worker threads do not survive fork), and one closed or left alive at the child's exit
        # aborted it (joining threads that are not there). Refused there, naming both processes;
        # a copy made in the child, a batch of 1 thread and a single Env work. Each child exits with
        # a code its parent checks, within a time limit; all in a process of its own, so that a hang
        # or a crash fails this test rather than the suite.
        child = textwrap.dedent("""
            import copy, os, sys, time
            import numpy as np
            import roger
            vec = roger.make_vec(sys.argv[1], "Look", "Gaze", 4, threads=2)
            one = roger.make_vec(sys.argv[1], "Look", "Gaze", 2, threads=1)
            env = roger.make(sys.argv[1], "Look", "Gaze")
            vec.reset(seed=1)
            one.reset(seed=1)
            env.reset(seed=1)
            def fork(child):
                pid = os.fork()
                if pid == 0:
                    child()
                    os._exit(0)
                deadline = time.time() + 60
                while True:
                    done, status = os.waitpid(pid, os.WNOHANG)
                    if done:
                        return os.waitstatus_to_exitcode(status)
                    if time.time() > deadline:
                        os.kill(pid, 9)
                        os.waitpid(pid, 0)
                        return "hung"
                    time.sleep(0.05)
            def uses():
                code = 42
                for call in (lambda: vec.step(np.zeros(4, int)), vec.reset, vec.render):
                    try:
                        call()
                        code = 10  # not refused
                    except roger.RogerError as e:
                        if (f"this make_vec batch was made in process {os.getppid()} and is used in process "
                                f"{os.getpid()} (a fork()ed child)" not in str(e)
                                or "make a new batch in this process" not in str(e)):
                            code = 11
                twin = copy.deepcopy(vec)  # a batch of the child's own, which continues the worlds
                seeds = twin.step(np.zeros(4, int))[4]["seed"].tolist()
                one.step(np.zeros(2, int))
                env.step(0)
                vec.close()  # its threads are not joined here
                os._exit(code if seeds == [1, 2, 3, 4] else 12)
            def exits():
                sys.exit(43)  # the interpreter's end frees the batch, alive
            print(repr((fork(uses), fork(exits), vec.step(np.zeros(4, int))[4]["seed"].tolist())))
            """)
        try:
            out = subprocess.run([sys.executable, "-c", child, EXAMPLE], capture_output=True, text=True, timeout=240)
        except subprocess.TimeoutExpired:
            self.fail("a batch used in a forked child hung")
        self.assertEqual(out.returncode, 0, out.stderr[-3000:])
        uses, exits, parent = eval(out.stdout.strip().splitlines()[-1])
        self.assertEqual((uses, exits), (42, 43), out.stderr[-3000:])
        self.assertEqual(parent, [1, 2, 3, 4])  # the parent's batch goes on

    def test_exit_while_a_daemon_thread_steps(self):
        # Found by a probe: the interpreter exiting (at the script's end, or on Ctrl-C) while a daemon
        # thread stepped an Env or a make_vec batch aborted the process ("terminate called without an
        # active exception", exit code 134): CPython ends such a thread as it takes the GIL back.
        child = textwrap.dedent("""
            import os, signal, sys, threading, time
            import numpy as np
            import roger
            if sys.argv[2] == "vec":
                v = roger.make_vec(sys.argv[1], "SG", "DC2", 4, threads=2)
                v.reset(seed=0)
                def loop():
                    while True:
                        v.step(np.zeros(4, int))
            else:
                e = roger.make(sys.argv[1], "T", "B2")
                e.reset(seed=0)
                def loop():
                    while True:
                        if any(e.step(0)[2:4]):
                            e.reset()
            threading.Thread(target=loop, daemon=True).start()
            time.sleep(0.3)
            print("exiting", flush=True)
            if sys.argv[3] == "interrupt":
                os.kill(os.getpid(), signal.SIGINT)
                time.sleep(5)
            """)
        for kind in ("env", "vec"):
            for how in ("end", "interrupt"):
                with self.subTest(kind=kind, how=how):
                    out = subprocess.run([sys.executable, "-c", child, PAPER, kind, how], capture_output=True,
                                         text=True, timeout=120)
                    self.assertNotIn("terminate called", out.stderr)
                    if how == "end":
                        self.assertEqual(out.returncode, 0, out.stderr[-3000:])
                    else:  # Python's own exit on an uncaught KeyboardInterrupt
                        self.assertIn("KeyboardInterrupt", out.stderr)
                        self.assertIn(out.returncode, (1, -signal.SIGINT, 128 + signal.SIGINT), out.stderr[-3000:])
                    self.assertEqual(out.stdout, "exiting\n")

    def test_policies_copy_bind_skills_and_keep_their_table(self):
        # Found by a probe: a loaded Policy neither pickled nor deep-copied (environments holding one
        # did), skills= took a policy's path but not the Policy, and a write to .q changed nothing.
        policy = roger.load_policy(train(EXAMPLE, "Look", "Gaze", 3, "look"))
        self.assertFalse(policy.q.flags.writeable)
        with self.assertRaises(ValueError):
            policy.q[0, 0] = 5.0
        for twin in (copy.deepcopy(policy), pickle.loads(pickle.dumps(policy))):
            np.testing.assert_array_equal(twin.q, policy.q)
            self.assertEqual((twin.stage, twin.context, twin.actions, twin.seed, twin.curriculum),
                             (policy.stage, policy.context, policy.actions, policy.seed, policy.curriculum))
            self.assertEqual(twin.path, os.path.abspath(policy.path))
        sg = roger.load_policy(train(PAPER, "SG", "DC2", 1, "sg-dc2"))
        by_policy = roger.make(PAPER, "T", "DC6", skills={"Phi_SG": sg})
        by_path = roger.make(PAPER, "T", "DC6", skills={"Phi_SG": sg.path})
        for e in (by_policy, by_path):
            e.reset(seed=FIRST_SEED)
        twin = copy.deepcopy(by_policy)
        for a in (0, 1, 2, 0, 1):
            step = by_policy.step(a)
            assert_same_step(self, step, by_path.step(a), f"action {a}")
            assert_same_step(self, step, twin.step(a), f"a copy, action {a}")
            if step[2] or step[3]:
                break
        vec = roger.make_vec(PAPER, "T", "DC6", 2, threads=1, skills={"Phi_SG": sg})
        np.testing.assert_array_equal(vec.reset(seed=FIRST_SEED)[0][0], by_path.reset(seed=FIRST_SEED)[0])

    def test_copy_of_a_faulted_episode(self):
        env = roger.make(BAD_REWARD, "Look", "Gaze")
        env.reset(seed=1)
        with self.assertRaises(roger.ScriptError):
            for _ in range(500):
                env.step(0)
        twin = pickle.loads(pickle.dumps(env))  # the replay meets the fault again, quietly
        self.assertRaisesRegex(roger.RogerError, "call reset", twin.step, 0)
        np.testing.assert_array_equal(twin.reset(seed=2)[0], env.reset(seed=2)[0])

    def test_vector_copies_continue(self):
        for mode in ("NextStep", "SameStep"):
            vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=3, threads=2, autoreset_mode=mode)
            vec.reset(seed=60)
            rng = np.random.default_rng(8)
            for _ in range(17):
                vec.step(rng.integers(0, 2, size=3))
            copies = [pickle.loads(pickle.dumps(vec)), copy.deepcopy(vec)]
            for k in range(60):
                actions = rng.integers(0, 2, size=3)
                results = [v.step(actions) for v in [vec] + copies]
                for r in results[1:]:
                    assert_same_step(self, results[0], r, f"{mode}: step {k}")
            resets = [v.reset() for v in [vec] + copies]  # the same schedule
            for r in resets[1:]:
                assert_same_step(self, resets[0], r, f"{mode}: unseeded reset")
        # A faulted environment is over in the copy too, and begins anew at the same step.
        vec = roger.make_vec(TIMEOUT_FAULT, "Look", "Gaze", num_envs=3, threads=2)
        vec.reset(seed=100)
        self.assertRaises(roger.ScriptError, vec.step, np.array([0, 1, 0]))
        twin = copy.deepcopy(vec)
        outcomes = []
        for v in (vec, twin):
            try:
                outcomes.append(v.step(np.array([0, 1, 0])))
            except roger.ScriptError as e:
                outcomes.append(e.results)
        assert_same_step(self, outcomes[0], outcomes[1], "after a fault")
        self.assertEqual(outcomes[1][4]["seed"][1], 104)

    def test_is_success(self):
        # Stable-Baselines3's Monitor and EvalCallback read info["is_success"] at an episode's end.
        env = roger.make(EXAMPLE, "Look", "Gaze")
        _, info = env.reset(seed=3)
        self.assertNotIn("is_success", info)
        done = False
        while not done:
            _, _, terminated, truncated, info = env.step(1)
            done = terminated or truncated
        self.assertEqual(info["is_success"], info["success"])
        self.assertTrue(info["is_success"])
        for mode in ("NextStep", "SameStep"):
            vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=2, threads=1, autoreset_mode=mode)
            vec.reset(seed=3)
            ended = np.zeros(2, bool)
            while not ended.any():
                _, _, ended, _, info = vec.step(np.array([1, 1]))
            where = info["final_info"] if mode == "SameStep" else info
            np.testing.assert_array_equal(where["is_success"], where["success"])
            np.testing.assert_array_equal(where["_is_success"], ended)

    def test_tick_observations_in_their_spaces(self):
        # float32 everywhere but the images (uint8) and the state; finite bounds where the body
        # gives them; readings pushed or noised past a joint's range are held at its bound.
        env = roger.make(EXAMPLE, "Look", "Gaze", mode="tick", params={"noise_joints": 0.5})
        space = env.observation_space
        for key in ("stimulus", "touch", "joints", "joint_velocities"):
            self.assertEqual(space[key].dtype, np.float32, key)
        joints = space["joints"]
        self.assertEqual((joints.low[0], joints.high[0]), (-np.inf, np.inf))  # the odometer
        self.assertTrue(np.isfinite(joints.low[1:]).all() and np.isfinite(joints.high[1:]).all())
        np.testing.assert_array_equal(joints.high[2:], np.float32([np.pi / 2, np.pi / 2, 3.0, 2.9, 3.0, 2.9]))
        np.testing.assert_array_equal(space["touch"].low[0], [0, 0, 0, -1, -1])
        np.testing.assert_array_equal(space["touch"].high[0], [1, np.inf, np.inf, 1, 1])
        obs, _ = env.reset(seed=5)
        rng = np.random.default_rng(2)
        at_bound = 0
        for _ in range(200):
            for key in ("stimulus", "touch", "joints", "joint_velocities"):
                self.assertEqual(obs[key].dtype, np.float32, key)
            self.assertTrue(space.contains(obs), obs)
            at_bound += int(np.count_nonzero((obs["joints"] == joints.low) | (obs["joints"] == joints.high)))
            obs, _, terminated, truncated, _ = env.step(int(rng.integers(2)))
            if terminated or truncated:
                obs, _ = env.reset()
        self.assertGreater(at_bound, 0)  # noise of 0.5 rad took eye readings past +-pi/2: held there

    def test_time_out_as_truncation(self):
        # timeout="truncate": the stage's time-out is a truncation (its reward unchanged); the
        # absorbing state still terminates. The default stays terminal.
        env = roger.make(EXAMPLE, "Look", "Gaze", timeout="truncate")
        env.reset(seed=3)
        terminated = truncated = False
        while not (terminated or truncated):
            _, reward, terminated, truncated, info = env.step(0)  # searching for ever times out
        self.assertEqual((terminated, truncated, info["time_out"], reward), (False, True, True, -100.0))
        env.reset(seed=3)
        while not env.step(1)[2]:
            pass  # terminated at the goal
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=1, threads=1, timeout="truncate")
        vec.reset(seed=3)
        terminated = truncated = np.array([False])
        while not (terminated[0] or truncated[0]):
            _, reward, terminated, truncated, info = vec.step(np.array([0]))
        self.assertEqual((terminated[0], truncated[0], info["time_out"][0], reward[0]), (False, True, True, -100.0))
        self.assertRaisesRegex(roger.RogerError, "timeout", roger.make, EXAMPLE, "Look", "Gaze", timeout="never")
        self.assertRaisesRegex(roger.RogerError, "timeout", roger.make_vec, EXAMPLE, "Look", "Gaze", 1, timeout=1)

    def test_the_interpreter_keeps_subnormals(self):
        # The engine flushes subnormals to zero while it runs an episode (World::reset); the
        # caller's thread gets its own floating-point mode back after every call, so numpy and
        # torch in the learner's thread compute as IEEE says.
        tiny = np.array([5e-324])
        env = roger.make(EXAMPLE, "Look", "Gaze", render_mode="rgb_array", render_width=200)
        env.reset(seed=1)
        env.step(0)
        env.render()
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=2, threads=2)
        vec.reset(seed=1)
        vec.step(np.array([0, 1]))
        self.assertEqual((tiny * 1.0)[0], 5e-324)

    def test_unknown_reset_options_are_refused(self):
        env = roger.make(EXAMPLE, "Look", "Gaze")
        with self.assertRaises(roger.RogerError) as cm:
            env.reset(seed=1, options={"params": {"shape": "spade"}})
        self.assertIn("'params'", str(cm.exception))
        self.assertIn("known options: 'task'", str(cm.exception))
        env.reset(seed=1, options={})  # empty options are fine (Gymnasium's checker passes them)
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=2, threads=1)
        with self.assertRaises(roger.RogerError) as cm:
            vec.reset(options={"mask": np.array([True, False])})
        self.assertIn("'mask'", str(cm.exception))
        self.assertIn("'reset_mask'", str(cm.exception))


TEACHERS = "curricula/teachers.lua"
PLR_TD = ("plr's default), which an environment stepped from outside does not have: give it score = "
          """"success" from Python, roger.make(..., teacher='roger.teacher.plr{score = "success"}')""")
# The tutorial's stage over a space given from Python (its scenario has both parameters).
LOOK_TASKS = {"robot_distance": roger.axis.real(0.6, 2.0), "shape": roger.axis.choice(["circle", "spade"])}
# Told each outcome: its distance counts the episodes told so far, its shape says whether the last
# one succeeded.
COUNTING_TEACHER = """function(history, rng)
  local n = #history
  return { robot_distance = 0.6 + 0.1 * (n % 5), shape = (n > 0 and history[n].success) and "spade" or "circle" }
end"""


def task_episode(env, seed=None, options=None, actions=None):
    """One episode: actions from the list `actions` (then search), or centre the ball once seen
    (phi0), else search. Returns what the episode was: its task, world, steps and outcome."""
    obs, info = env.reset(seed=seed, options=options)
    record = {"task": info.get("task"), "params": info.get("task_params"), "seed": info["seed"], "steps": []}
    done, k = False, 0
    while not done:
        a = (actions[k] if k < len(actions) else 0) if actions is not None else (1 if obs[1] else 0)
        obs, reward, terminated, truncated, info = env.step(a)
        record["steps"].append((tuple(int(x) for x in obs), reward, info["ticks"]))
        done, k = terminated or truncated, k + 1
    record.update(success=info["success"], reward=info["episode_reward"], sim_seconds=info["sim_seconds"])
    return record


class Tasks(unittest.TestCase):
    """Task spaces and teachers from Python (docs/python.md, Tasks and teachers): the stage's space
    as a Dict space, tasks given in reset's options or set_task and refused outside the space, the
    engine's teachers run on resets without a task, told each outcome, deterministic, copied."""

    def test_copies_keep_the_spaces_generators(self):
        # Found by a probe: a copy made its spaces afresh, unseeded, so a worker's copy drew other
        # tasks (sample_tasks) and other actions than the original, which a deepcopy of Gymnasium's
        # own environments (and of its spaces) does not.
        env = roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS, teacher=False)
        env.task_space.seed(7)
        env.action_space.seed(0)
        env.observation_space.seed(1)
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=2)
        vec.action_space.seed(3)
        vec.single_action_space.seed(4)
        for copied in (copy.deepcopy, lambda e: pickle.loads(pickle.dumps(e))):
            twin = copied(env)
            self.assertEqual(repr(twin.sample_tasks(4)), repr(env.sample_tasks(4)))
            self.assertEqual([twin.action_space.sample() for _ in range(8)], [env.action_space.sample() for _ in range(8)])
            np.testing.assert_array_equal(twin.observation_space.sample(), env.observation_space.sample())
            vec_twin = copied(vec)
            np.testing.assert_array_equal(vec_twin.action_space.sample(), vec.action_space.sample())
            self.assertEqual(vec_twin.single_action_space.sample(), vec.single_action_space.sample())

    def test_stage_task_space(self):
        space = roger.make(TEACHERS, "T_alp", "B2").task_space
        self.assertIsInstance(space, roger.spaces.Dict)
        self.assertEqual(sorted(space.spaces), ["obstacles", "robot_distance", "shape"])
        self.assertEqual((space["obstacles"].n, int(space["obstacles"].start)), (7, 0))  # roger.int(0, 6)
        self.assertEqual(space["shape"].n, 4)  # the four shapes, by index
        box = space["robot_distance"]
        self.assertEqual((box.shape, box.dtype, float(box.low), float(box.high)), ((), np.float64, 0.8, 2.0))
        # What params fix leaves the space, as --set does for roger train.
        fixed = roger.make(TEACHERS, "T_alp", "B2", params={"obstacles": 2}).task_space
        self.assertEqual(sorted(fixed.spaces), ["robot_distance", "shape"])
        self.assertIsNone(roger.make(EXAMPLE, "Look", "Gaze").task_space)
        ints = roger.make(EXAMPLE, "Look", "Gaze", tasks={"eye_pixels": "roger.int(32, 40)"}).task_space
        self.assertEqual((ints["eye_pixels"].n, int(ints["eye_pixels"].start)), (9, 32))

    def test_task_generates_the_world(self):
        # A task's world is the world of its parameters given as params: the same steps under the
        # same actions, and not the stage's own world (the task is not ignored).
        env = roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS, teacher=False)
        fixed = roger.make(EXAMPLE, "Look", "Gaze", params={"robot_distance": 0.6, "shape": "spade"})
        plain = roger.make(EXAMPLE, "Look", "Gaze")
        differ = 0
        for seed in (1, 2, 3):
            acts = list(np.random.default_rng(seed).integers(2, size=40))
            task = task_episode(env, seed, {"task": {"robot_distance": 0.6, "shape": "spade"}}, acts)
            self.assertEqual(task["steps"], task_episode(fixed, seed, actions=acts)["steps"])
            self.assertEqual(task["params"], {"robot_distance": 0.6, "shape": "spade"})
            differ += task["steps"] != task_episode(plain, seed, actions=acts)["steps"]
            # A reset without a task has the stage's parameters again, not the last task's.
            self.assertEqual(task_episode(env, seed, actions=acts)["steps"], task_episode(plain, seed, actions=acts)["steps"])
        self.assertGreater(differ, 0)

    def test_tasks_as_the_space_holds_them(self):
        env = roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS, teacher=False)
        by_index = env.reset(seed=4, options={"task": {"robot_distance": 1.25, "shape": 1}})[1]
        by_value = env.reset(seed=4, options={"task": {"robot_distance": 1.25, "shape": "spade"}})[1]
        self.assertEqual(by_index["task"], {"robot_distance": 1.25, "shape": 1})
        self.assertEqual(by_index["task"], by_value["task"])
        self.assertEqual(by_index["task_params"], {"robot_distance": 1.25, "shape": "spade"})
        env.task_space.seed(3)
        for _ in range(5):
            sample = env.task_space.sample()
            env.reset(seed=4, options={"task": sample})
            self.assertTrue(env.task_space.contains(env.get_task()))
            self.assertEqual(env.get_task()["robot_distance"], float(sample["robot_distance"]))
            self.assertEqual(env.get_task()["shape"], int(sample["shape"]))
        self.assertIsNone(env.reset(seed=4)[1]["task"])  # no teacher: the stage's parameters

    def test_task_params_are_numbers(self):
        # info["task_params"] and task_params(): an int axis's value an int, a real's a float, a
        # choice's its value (the scenario's text), with the exact value the scenario took.
        env = roger.make(TEACHERS, "T_alp", "B2")
        _, info = env.reset(seed=1)
        params = info["task_params"]
        self.assertEqual(sorted(params), ["obstacles", "robot_distance", "shape"])
        self.assertIs(type(params["obstacles"]), int)
        self.assertIs(type(params["robot_distance"]), float)
        self.assertIsInstance(params["shape"], str)
        self.assertEqual(params["robot_distance"], float(info["task"]["robot_distance"]))
        self.assertEqual(env.task_params(info["task"]), params)
        task = {"obstacles": 2, "robot_distance": 1.0, "shape": 0}
        self.assertEqual(env.task_params(task), {"obstacles": 2, "robot_distance": 1.0, "shape": "circle"})
        self.assertIs(type(env.task_params(task)["robot_distance"]), float)  # 1.0, not the text's 1
        self.assertEqual(env.reset(seed=1, options={"task": task})[1]["task_params"], env.task_params(task))

    def test_bad_tasks(self):
        env = roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS, teacher=False)
        space = "robot_distance = roger.real(0.6, 2), shape = roger.choice{circle, spade}"
        for task, texts in (
                ({"robot_distance": 1.0, "shape": 0, "mass": 1}, ["'mass' is not a parameter of the task space", space]),
                ({"robot_distance": 2.5, "shape": 0}, ["robot_distance = 2.5 is outside the task space",
                                                       "roger.real(0.6, 2)"]),
                ({"robot_distance": True, "shape": 0}, ["robot_distance = true is outside the task space"]),
                ({"robot_distance": 1.0, "shape": 2}, ["shape = 2 is outside", "an index in [0, 2)"]),
                ({"robot_distance": 1.0, "shape": "star"}, ["shape = star is outside", "roger.choice{circle, spade}"]),
                ({"shape": 0}, ["no value for 'robot_distance'"]),
                (3, ["a task is a dict", space])):
            with self.subTest(task=task):
                with self.assertRaises(roger.RogerError) as cm:
                    env.reset(seed=1, options={"task": task})
                self.assertIn("reset: options['task']", str(cm.exception))
                for t in texts:
                    self.assertIn(t, str(cm.exception))
                with self.assertRaises(roger.RogerError) as cm:
                    env.set_task(task)
                self.assertIn("set_task", str(cm.exception))
        env.reset(seed=1)  # still usable
        with self.assertRaises(roger.RogerError) as cm:
            roger.make(EXAMPLE, "Look", "Gaze").reset(options={"task": {"shape": 0}})
        self.assertIn("no task space", str(cm.exception))

    def test_bad_make(self):
        def script_error(texts, **kwargs):
            with self.assertRaises(roger.ScriptError) as cm:
                roger.make(EXAMPLE, "Look", "Gaze", **kwargs).reset(seed=1)
            for t in texts:
                self.assertIn(t, str(cm.exception))
            return cm.exception
        e = script_error(["tasks.nope = roger.int(0, 3)", "has no parameter 'nope'"], tasks={"nope": roger.axis.int(0, 3)})
        self.assertEqual((e.file, e.line), ("make(tasks=...)", 1))
        script_error(["tasks.shape", "got 'star'"], tasks={"shape": roger.axis.choice(["circle", "star"])})
        script_error(["tasks.robot_distance", "at least 0"], tasks={"robot_distance": roger.axis.real(-1, 1)})
        e = script_error(["roger.teacher.lcas", "'lift'"], tasks=LOOK_TASKS, teacher="roger.teacher.lcas{}")
        self.assertEqual(e.file, "make(teacher=...)")
        script_error(["step 1", "outside the task space"], tasks=LOOK_TASKS,
                     teacher='roger.teacher.sequence{ {shape = "star"} }')
        script_error(["needs a task space"], teacher="roger.teacher.random{}")
        script_error(["gives no value for 'teacher'"], tasks=LOOK_TASKS, teacher="local x = 1")
        path = os.path.join(WORK, "bad_teacher.lua")
        with open(path, "w") as f:
            f.write('return function(history, rng)\n  return { shape = "star" }\nend\n')
        e = script_error(["returned shape = star, outside the task space", "roger.choice{circle, spade}"],
                         tasks=LOOK_TASKS, teacher=path)
        self.assertTrue(e.file.endswith("bad_teacher.lua"), e.file)
        # Found by a probe: the message said score = "success" without saying where to give it.
        for kwargs, text in ((dict(tasks=LOOK_TASKS, teacher="roger.teacher.plr{}"), PLR_TD),
                             (dict(tasks=LOOK_TASKS, teacher=42), "teacher must be"),
                             (dict(tasks=LOOK_TASKS, teacher="missing.lua"), "names no file"),
                             (dict(tasks={}), "tasks must be"),
                             (dict(tasks={"shape": 3}), "tasks['shape']")):
            with self.subTest(kwargs=kwargs):
                with self.assertRaises(roger.RogerError) as cm:
                    roger.make(EXAMPLE, "Look", "Gaze", **kwargs)
                self.assertIn(text, str(cm.exception))
        self.assertRaises(roger.RogerError, roger.axis.real, 0, float("inf"))
        self.assertRaises(roger.RogerError, roger.axis.choice, "circle")
        with self.assertRaises(roger.RogerError) as cm:
            roger.make(TEACHERS, "T_plr", "B2")  # the stage's plr{}: td by default
        self.assertIn(PLR_TD, str(cm.exception))
        with self.assertRaises(roger.RogerError) as cm:
            roger.make_vec(TEACHERS, "T_alp", "B2", num_envs=2)
        self.assertIn("chooses each episode's task with a teacher", str(cm.exception))

    def test_params_fixing_a_task_axis(self):
        # Found by a probe: tasks varying a parameter params fix lost the axis silently (a random
        # teacher over nothing); refused, as the curriculum refuses it of a stage's own params.
        with self.assertRaises(roger.RogerError) as cm:
            roger.make(PAPER, "T", "B2", tasks={"robot_distance": roger.axis.real(0.8, 2)},
                       params={"robot_distance": 1.5})
        self.assertIn("stage 'T': make(tasks=...) varies 'robot_distance', which make's params fix "
                      "(robot_distance=1.5); remove one of them", str(cm.exception))
        # The stage's own axes, all fixed by params: a teacher that needs a space says why it has none.
        with self.assertRaises(roger.RogerError) as cm:
            roger.make(TEACHERS, "T_alp", "B2", params={"obstacles": 2, "shape": "spade", "robot_distance": 1.5})
        for text in ("needs a task space with at least one parameter", "make's params fix every axis of the stage's "
                     "task space ('obstacles', 'robot_distance', 'shape')", "teacher=False"):
            self.assertIn(text, str(cm.exception))
        env = roger.make(TEACHERS, "T_alp", "B2", params={"obstacles": 2})  # one fixed: the others vary
        self.assertEqual(sorted(env.task_space.keys()), ["robot_distance", "shape"])

    def test_a_scenario_that_cannot_play_the_task_space(self):
        # Found by a probe: make(TEACHERS, "T_alp", "B2", scenario="unobstructed") was made, and its
        # first reset failed on 'obstacles' (no "reset:", no task named); with teacher=False the
        # task space still offered it. A task space the scenario given cannot take is refused at make.
        for teacher in (None, False):
            with self.subTest(teacher=teacher):
                with self.assertRaises(roger.RogerError) as cm:
                    roger.make(TEACHERS, "T_alp", "B2", scenario="unobstructed", teacher=teacher)
                for text in ("make: scenario='unobstructed' cannot play the task space of stage 'T_alp'",
                             "curricula/teachers.lua:", "tasks.obstacles = roger.int(", "scenario 'unobstructed'", "has no parameter 'obstacles'",
                             "known parameters"):
                    self.assertIn(text, str(cm.exception))
        # Given tasks are checked against the scenario given (when the stage's has them too).
        with self.assertRaises(roger.RogerError) as cm:
            roger.make(TEACHERS, "T_alp", "B2", scenario="unobstructed", tasks={"obstacles": roger.axis.int(0, 2)})
        for text in ("stage 'T_alp': tasks.obstacles = roger.int(0, 2)", "scenario 'unobstructed'",
                     "has no parameter 'obstacles'"):
            self.assertIn(text, str(cm.exception))
        # And only against it: the paper's T plays 'unobstructed', which has no obstacles; given
        # scenario='cluttered', a space over obstacles is taken (it was refused, asked of 'unobstructed').
        env = roger.make(PAPER, "T", "B2", scenario="cluttered", tasks={"obstacles": roger.axis.int(0, 6)})
        self.assertIn(env.reset(seed=1)[1]["task_params"]["obstacles"], range(7))
        # A scenario that takes the space plays it.
        env = roger.make(TEACHERS, "T_alp", "B2", scenario="cluttered")
        self.assertEqual(sorted(env.task_space.keys()), ["obstacles", "robot_distance", "shape"])
        env.reset(seed=1)
        env = roger.make(PAPER, "T", "B2", scenario="cluttered", tasks={"robot_distance": roger.axis.real(1, 2)})
        self.assertTrue(1 <= env.reset(seed=1)[1]["task_params"]["robot_distance"] <= 2)

    def test_make_vec_without_the_teacher(self):
        # Found by a probe: make_vec took no teacher argument; teacher=False plays the stage's own
        # parameters, as make(..., teacher=False) does.
        vec = roger.make_vec(TEACHERS, "T_alp", "B2", 2, teacher=False)
        obs, info = vec.reset(seed=11)
        for i in range(2):
            single_obs, single_info = roger.make(TEACHERS, "T_alp", "B2", teacher=False).reset(seed=11 + i)
            np.testing.assert_array_equal(obs[i], single_obs)
            self.assertEqual(info["sim_seconds"][i], single_info["sim_seconds"])
        self.assertEqual(pickle.loads(pickle.dumps(vec)).reset(seed=11)[1]["seed"].tolist(), [11, 12])
        with self.assertRaises(roger.RogerError) as cm:
            roger.make_vec(TEACHERS, "T_alp", "B2", 2)
        self.assertIn("give make_vec(..., teacher=False) for the stage's own parameters", str(cm.exception))
        with self.assertRaises(roger.RogerError) as cm:
            roger.make_vec(TEACHERS, "T_alp", "B2", 2, teacher="roger.teacher.random{}")
        self.assertIn("make_vec: teacher is None (the stage's, refused when it has one) or False (none)",
                      str(cm.exception))

    def test_without_the_teacher_params_may_fix_what_it_lifts(self):
        # Found by a probe: a policy trained under LCAS records the level it reached, and
        # policy.make() (teacher=False) was refused for fixing "the parameter its teacher lifts".
        policy = roger.load_policy(train(LCAS_LIFT, "S", "Gaze", 1, "lcas_lift"))
        self.assertEqual(policy.params, {"eye_pixels": "32"})
        env = policy.make(mode="tick")
        self.assertEqual(env.reset(seed=1)[0]["images"].shape, (2, 32, 3))
        obs, _ = roger.make(TEACHERS, "SG_lcas", "B1", mode="tick", teacher=False, params={"eye_pixels": 64}).reset(seed=1)
        self.assertEqual(obs["images"].shape, (2, 64, 3))
        vec = roger.make_vec(TEACHERS, "SG_lcas", "B1", 2, teacher=False, params={"eye_pixels": 64})
        self.assertEqual(vec.stage_info["eye_pixels"], 64)
        # With the teacher, fixing its lift is still refused, and the way out named.
        with self.assertRaises(roger.ScriptError) as cm:
            roger.make(TEACHERS, "SG_lcas", "B1", params={"eye_pixels": 32})
        for text in ("teachers.lua:87", "'eye_pixels' is fixed by make's params", "or give teacher=False for none"):
            self.assertIn(text, str(cm.exception))

    def test_teacher_is_told_each_outcome(self):
        env = roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS, teacher=COUNTING_TEACHER)
        last = None
        for n in range(8):  # the rule succeeds, searching alone times out: outcomes alternate
            r = task_episode(env, seed=11 if n == 0 else None, actions=[0] * 400 if n % 2 else None)
            self.assertAlmostEqual(r["params"]["robot_distance"], 0.6 + 0.1 * (n % 5), places=12)
            self.assertEqual(r["params"]["shape"], "spade" if last else "circle")
            self.assertEqual(r["success"], n % 2 == 0)
            last = r["success"]
        self.assertEqual(env.teacher_state["episodes"], 8)
        # An episode left unfinished is told as it stood (not a success) at the next reset.
        env.reset()
        env.step(0)
        obs, info = env.reset()
        self.assertEqual(info["task_params"]["shape"], "circle")
        self.assertEqual(env.teacher_state["episodes"], 9)
        # A seeded reset starts the teacher afresh, as it starts the stream of worlds.
        self.assertEqual(env.reset(seed=11)[1]["task_params"], {"robot_distance": 0.6, "shape": "circle"})

    def teacher_run(self, seed, episodes=25, teacher="roger.teacher.alp_gmm{fit_every = 10}"):
        env = roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS, teacher=teacher)
        rng = np.random.default_rng(seed)
        runs = [task_episode(env, seed if e == 0 else None, actions=list(rng.integers(2, size=60)))
                for e in range(episodes)]
        return runs, env.teacher_state

    def test_teachers_are_deterministic(self):
        for teacher in ("roger.teacher.alp_gmm{fit_every = 10}", 'roger.teacher.plr{score = "success"}',
                        "roger.teacher.random{}"):
            with self.subTest(teacher=teacher):
                a, state = self.teacher_run(5, teacher=teacher)
                b, again = self.teacher_run(5, teacher=teacher)
                self.assertEqual(a, b)
                self.assertEqual(state, again)
                self.assertEqual(state["episodes"], 25)
                c, _ = self.teacher_run(6, teacher=teacher)
                self.assertNotEqual([r["task"] for r in a], [r["task"] for r in c])
        self.assertEqual(state.get("kind"), "random")
        alp = self.teacher_run(5)[1]
        self.assertEqual(alp["fits"], 2)  # fit_every = 10: after episodes 10 and 20

    def test_no_task_is_the_teachers(self):
        # Found by a probe: options={"task": None} was refused, while set_task(None) hands the
        # choice back to the teacher; it is no task option now.
        env, twin = (roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS, teacher=COUNTING_TEACHER)
                     for _ in range(2))
        for e in range(4):
            seed = 1 if e == 0 else None
            _, info = env.reset(seed=seed, options={"task": None})
            _, twin_info = twin.reset(seed=seed)
            self.assertEqual(info["task_params"], twin_info["task_params"])
        task = {"robot_distance": 1.5, "shape": 1}
        env.set_task(task)
        self.assertEqual(env.reset(options={"task": None})[1]["task_params"], env.task_params(task))

    def test_sample_tasks_counts_and_seeds(self):
        # Found by a probe: sample_tasks(-1) gave [] silently and sample_tasks(1.5) a raw TypeError.
        env = roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS)
        self.assertEqual(env.sample_tasks(0), [])  # as random.sample(..., 0)
        self.assertEqual(len(env.sample_tasks(np.int64(2))), 2)
        for bad in (-1, 1.5, True, "2", None):
            with self.subTest(n=bad):
                self.assertRaisesRegex(roger.RogerError, r"sample_tasks: a count of tasks is a non-negative integer, "
                                                         f"got {re.escape(repr(bad))}", env.sample_tasks, bad)
        drawn = []
        for _ in range(2):  # seeded through task_space, the same tasks
            env.task_space.seed(5)
            drawn.append(repr(env.sample_tasks(3)))
        self.assertEqual(drawn[0], drawn[1])

    def test_set_task(self):
        env = roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS, teacher="roger.teacher.alp_gmm{fit_every = 10}")
        tasks = env.sample_tasks(4)
        self.assertTrue(all(env.task_space.contains(t) for t in tasks))
        env.set_task(tasks[0])
        for seed in (1, None, None):
            self.assertEqual(env.reset(seed=seed)[1]["task"], env.get_task())
            self.assertEqual(env.get_task()["shape"], int(tasks[0]["shape"]))
        self.assertIsNone(env.teacher_state)  # never asked
        env.reset(options={"task": tasks[1]})  # for one episode
        self.assertEqual(env.get_task()["robot_distance"], float(tasks[1]["robot_distance"]))
        self.assertEqual(env.reset()[1]["task"]["robot_distance"], float(tasks[0]["robot_distance"]))
        env.set_task(None)
        env.reset()
        self.assertEqual(env.teacher_state["kind"], "alp_gmm")

    def test_copies_continue_with_the_teacher(self):
        env = roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS, teacher="roger.teacher.alp_gmm{fit_every = 4}")
        for e in range(6):
            task_episode(env, 21 if e == 0 else None, actions=[e % 2] * 3)
        for _ in range(20):  # copied in the middle of an episode of the teacher's task
            env.reset()
            if not env.step(0)[2]:
                break
        copies = [copy.deepcopy(env), pickle.loads(pickle.dumps(env))]
        acts = list(np.random.default_rng(2).integers(2, size=30))
        runs, task = [], env.get_task()
        for e in (env, *copies):
            self.assertEqual(e.get_task(), task)
            obs, reward, terminated, truncated, info = e.step(0)  # the copies run on the same episode
            runs.append([(tuple(obs), reward, terminated, info["sim_seconds"])])
            runs[-1] += [task_episode(e, actions=acts) for _ in range(6)] + [e.teacher_state]
        self.assertEqual(runs[0], runs[1])
        self.assertEqual(runs[0], runs[2])

    def test_a_task_that_cannot_be_placed_is_skipped(self):
        # Beyond about 2 m from Roger the ball may find no place in the 4 x 4 m arena: the teacher's
        # task is skipped, as roger train skips it, and shown; the episode plays the next one.
        far = {"robot_distance": roger.axis.real(1.0, 3.4)}
        env = roger.make(EXAMPLE, "Look", "Gaze", tasks=far, teacher="roger.teacher.random{}")

        def resets(e, n, seed=None):
            out = []
            for k in range(n):
                info = e.reset(seed=seed if k == 0 else None)[1]
                out.append((float(info["task"]["robot_distance"]), info["skipped_tasks"]))
            return out

        runs = resets(env, 8, seed=3)
        skipped = [k for _, s in runs for k in s]
        self.assertEqual(len(skipped), 5)  # of 13 draws, the ones whose world had no room
        for k in skipped:
            self.assertGreater(float(k["task"]["robot_distance"]), 1.9, k)
            self.assertEqual(k["task_params"]["robot_distance"], float(k["task"]["robot_distance"]))
            self.assertIn("scenarios/lib/place.lua:91: world:sample_position: no placement for 'circle'", k["error"])
        self.assertEqual(resets(env, 8, seed=3), runs)  # the same skips again from the same seed
        self.assertEqual(env.teacher_state["episodes"], 7)  # the 7 earlier episodes, each told at the next reset; no skip
        # A copy's teacher asks the skipped tasks too, so it goes on with the same tasks.
        twin = copy.deepcopy(env)
        self.assertEqual(resets(twin, 6), resets(env, 6))
        # A task the caller gives is the caller's: its PlacementError (a ScriptError at the
        # scenario's line) is raised, not skipped.
        with self.assertRaises(roger.PlacementError) as cm:
            env.reset(options={"task": {"robot_distance": 3.3}})
        self.assertIsInstance(cm.exception, roger.ScriptError)
        self.assertEqual((cm.exception.file, cm.exception.line), ("scenarios/lib/place.lua", 91))
        # A space of worlds that cannot be built: the reset says so rather than drawing forever.
        holes = roger.make(EXAMPLE, "Look", "Gaze", tasks={"robot_distance": roger.axis.real(3.3, 3.4)},
                           teacher="roger.teacher.random{}")
        with self.assertRaises(roger.RogerError) as cm:
            holes.reset(seed=1)
        self.assertIn("the teacher's last 100 tasks could not be placed in 10 world seeds", str(cm.exception))
        # A narrow space that the layout of seed 26 cannot hold and others can (found by a probe: it
        # failed, drawing 100 tasks in that one layout): after 10 skips the draws move to another
        # world seed, roger.mix(26, 1), as roger train's do.
        narrow = roger.make(EXAMPLE, "Look", "Gaze", tasks={"robot_distance": roger.axis.real(2.1, 2.4)},
                            teacher="roger.teacher.random{}")
        info = narrow.reset(seed=26)[1]
        self.assertEqual(len(info["skipped_tasks"]), 10)
        self.assertEqual(int(info["seed"]), roger.mix(26, 1))

    def test_docs_example(self):
        # docs/python.md's example of tasks and teachers runs, and asserts what it says.
        with open("docs/python.md") as f:
            section = f.read().split("## Tasks and teachers", 1)[1].split("\n## ", 1)[0]
        code = section.split("```python\n", 1)[1].split("```", 1)[0]
        runs = []
        for _ in range(2):  # its sample_tasks are seeded: the task it sets is the same every run
            scope = {}
            exec(compile(code, "docs/python.md (Tasks and teachers)", "exec"), scope)
            runs.append(repr(scope["chosen"]))
        self.assertEqual(runs[0], runs[1])


class MissingToolProbe(unittest.TestCase):
    """SkipRule's probe: a test that needs the tool ROGER_TEST_PROBE_TOOL names (run by SkipRule)."""

    def test_needs_the_tool(self):
        tool = os.environ.get("ROGER_TEST_PROBE_TOOL")
        if not tool:
            self.skipTest("run by SkipRule alone")
        require(tool)


class SkipRule(unittest.TestCase):
    """A test whose tool is missing exits 77 (CTest shows it skipped), never 0; under CI=true it
    fails, unless docs/testing.md says CI cannot have the tool."""

    def probe(self, tool, ci, hidden=()):
        env = {k: v for k, v in os.environ.items() if k not in ("CI", "ROGER_TEST_WORK")}
        env["ROGER_TEST_PROBE_TOOL"] = tool
        if ci:
            env["CI"] = "true"
        if hidden:  # modules that fail to import, ahead of any installed copy
            folder = tempfile.mkdtemp(prefix="roger-hidden-")
            self.addCleanup(shutil.rmtree, folder, True)
            for name in hidden:
                os.makedirs(os.path.join(folder, name))
                with open(os.path.join(folder, name, "__init__.py"), "w") as f:
                    f.write("raise ImportError('hidden by SkipRule')\n")
            env["PYTHONPATH"] = folder + os.pathsep + env.get("PYTHONPATH", "")
        r = subprocess.run([sys.executable, os.path.abspath(__file__), "MissingToolProbe"], env=env,
                           capture_output=True, text=True, timeout=120)
        return r.returncode, r.stdout + r.stderr

    def test_missing_tool_is_a_skip(self):
        code, out = self.probe("roger_no_such_tool", ci=False)
        self.assertEqual(code, SKIP, out)
        self.assertIn("SKIPPED: missing tool: roger_no_such_tool", out)

    def test_missing_tool_fails_under_ci(self):
        code, out = self.probe("roger_no_such_tool", ci=True)
        self.assertEqual(code, 1, out)
        self.assertIn("FAILED (would skip, but CI=true): roger_no_such_tool", out)

    def test_tools_ci_cannot_have_skip_under_ci(self):
        for tool in NOT_IN_CI:
            with self.subTest(tool):
                code, out = self.probe(tool, ci=True, hidden=[tool])
                self.assertEqual(code, SKIP, out)
                self.assertIn(f"SKIPPED: missing tool: {tool}", out)

    def test_testing_md_names_the_tools_ci_cannot_have(self):
        with open("docs/testing.md") as f:
            text = f.read()
        self.assertIn("## Tools CI cannot have", text)
        section = text.split("## Tools CI cannot have", 1)[1].split("\n## ", 1)[0]
        for tool in NOT_IN_CI:
            self.assertIn(f"`{tool}`", section)


class GymnasiumJudges(unittest.TestCase):
    """Gymnasium's own checker, vectorizations and vector wrappers on the module, where gymnasium
    is importable (skipped elsewhere, and shown as skipped: the module does not need it)."""

    def setUp(self):
        self.gym = require("gymnasium")
        import warnings
        self.warnings = warnings

    def test_gymnasium_base(self):
        self.assertIsInstance(roger.make(EXAMPLE, "Look", "Gaze"), self.gym.Env)

    def check(self, env_id, **kwargs):
        from gymnasium.utils.env_checker import check_env
        for mode in ("decision", "tick"):
            with self.subTest(env_id=env_id, mode=mode), self.warnings.catch_warnings(record=True) as caught:
                self.warnings.simplefilter("always")
                env = self.gym.make(env_id, mode=mode, render_mode="rgb_array", **kwargs)
                self.assertIsInstance(env.unwrapped, roger.Env)
                check_env(env.unwrapped)  # the render check included
                messages = [str(w.message) for w in caught if "WARN" in str(w.message)]
                # The raw senses' unbounded boxes (touch forces, joints) are the only warnings.
                self.assertTrue(all("infinity" in m for m in messages), messages)
                self.assertTrue(mode == "tick" or not messages, messages)

    def test_check_env_paper_stages(self):
        self.check("roger/SG-B1-v0")
        self.check("roger/SG-DC2-v0")
        self.check("roger/T-DC6-v0", skills={"Phi_SG": train(PAPER, "SG", "DC2", 1, "sg-dc2")})

    def test_task_space(self):
        # A stage's task space is gymnasium's Dict of its Discrete and Box spaces, which its samples
        # and the environment's tasks are members of; check_env holds with a teacher (a seeded
        # reset starts it afresh).
        from gymnasium.utils.env_checker import check_env
        env = roger.make(TEACHERS, "T_alp", "B2")
        spaces = self.gym.spaces
        self.assertIsInstance(env.task_space, spaces.Dict)
        self.assertIsInstance(env.task_space["obstacles"], spaces.Discrete)
        self.assertIsInstance(env.task_space["shape"], spaces.Discrete)
        self.assertIsInstance(env.task_space["robot_distance"], spaces.Box)
        env.task_space.seed(1)
        for _ in range(3):
            task = env.task_space.sample()
            env.reset(seed=1, options={"task": task})
            self.assertIn(env.get_task(), env.task_space)
        env.reset(seed=1)
        self.assertIn(env.get_task(), env.task_space)  # the teacher's
        for teacher in (None, COUNTING_TEACHER):
            check_env(roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS, teacher=teacher))

    def test_spec_of_python_axes_is_json(self):
        # Found by a probe: spec.to_json() of an environment made with roger.axis values failed,
        # "Object of type Axis is not JSON serializable"; the spec keeps their Lua text.
        env = roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS)
        spec = self.gym.envs.registration.EnvSpec.from_json(env.spec.to_json())
        again = spec.make().unwrapped
        self.assertEqual(again.task_space, env.task_space)
        task = {"robot_distance": 1.3, "shape": "spade"}
        obs, info = env.reset(seed=4, options={"task": task})
        again_obs, again_info = again.reset(seed=4, options={"task": task})
        np.testing.assert_array_equal(obs, again_obs)
        self.assertEqual(info["task_params"], again_info["task_params"])
        self.assertEqual(repr(roger.make(EXAMPLE, "Look", "Gaze", tasks=LOOK_TASKS).spec.kwargs["tasks"]),
                         repr({k: v.lua for k, v in LOOK_TASKS.items()}))
        # Found by a probe: gymnasium.make's spec, set with the arguments as given, held the Axis and
        # the Policy and did not write to JSON.
        policy = roger.load_policy(train(EXAMPLE, "Look", "Gaze", 3, "look"))
        made = self.gym.make("roger/Stage-v0", curriculum=EXAMPLE, stage="Look", context="Gaze", tasks=LOOK_TASKS,
                             policy=policy)
        again = self.gym.make(self.gym.envs.registration.EnvSpec.from_json(made.spec.to_json()))
        self.assertEqual(again.unwrapped.task_space, made.unwrapped.task_space)
        self.assertEqual(made.unwrapped.spec.kwargs["policy"], policy.path)

    def test_registry(self):
        ids = [f"roger/SG-{c}-v0" for c in ("B1", "DC1", "DC2")] + \
              [f"roger/T-{c}-v0" for c in ("B2", "DC3", "DC4", "DC5", "DC6")] + ["roger/Stage-v0"]
        for env_id in ids:
            self.assertIn(env_id, self.gym.envs.registry)
        env = self.gym.make("roger/Stage-v0", curriculum=EXAMPLE, stage="Look", context="Gaze")
        self.assertEqual(env.unwrapped.actions, ("search", "phi0"))
        self.assertEqual(self.gym.make("roger/T-B2-v0").unwrapped.stage_info["context"], "B2")
        # roger.make's environments carry a spec that makes them again (check_env's render check).
        spec = roger.make(EXAMPLE, "Look", "Gaze").spec
        self.assertEqual(spec.make(render_mode="rgb_array").unwrapped.render_mode, "rgb_array")
        self.assertRaises(roger.RogerError, roger.make(EXAMPLE, "Look", "Gaze").reset, seed=-5)

    def test_vector_env(self):
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=4, threads=2)
        self.assertIsInstance(vec, self.gym.vector.VectorEnv)
        # gymnasium 1.0 names no modes (it autoresets at the next step only): then the package's enum.
        modes = getattr(self.gym.vector, "AutoresetMode", roger.AutoresetMode)
        self.assertIs(vec.metadata["autoreset_mode"], modes.NEXT_STEP)
        stats = self.gym.wrappers.vector.RecordEpisodeStatistics(vec)
        stats.reset(seed=5)
        stats.action_space.seed(5)
        ended = 0
        for _ in range(60):
            _, _, terminated, truncated, _ = stats.step(stats.action_space.sample())
            ended += int(np.count_nonzero(terminated | truncated))
        self.assertGreater(ended, 4)
        self.assertEqual(stats.episode_count, ended)
        self.assertEqual(len(stats.return_queue), min(ended, stats.return_queue.maxlen))

    def test_sync_vector_env_over_make(self):
        sync = self.gym.vector.SyncVectorEnv([lambda: roger.make(EXAMPLE, "Look", "Gaze") for _ in range(3)])
        vec = roger.make_vec(EXAMPLE, "Look", "Gaze", num_envs=3, threads=2)
        obs, _ = sync.reset(seed=20)
        np.testing.assert_array_equal(obs, vec.reset(seed=20)[0])
        rng = np.random.default_rng(2)
        same, resets = True, 0
        for k in range(40):
            actions = rng.integers(0, 2, size=3)
            s, v = sync.step(actions), vec.step(actions)
            self.assertTrue(sync.observation_space.contains(s[0]))
            # The infos' counts alike (found by a probe: make_vec's were int32, SyncVectorEnv's int64).
            for key in ("ticks", "decisions"):
                self.assertEqual(s[4][key].dtype, v[4][key].dtype, key)
            if same:  # the same episodes until the first autoreset (then make_vec's seeds step by
                for x, y in zip(s[:4], v[:4]):  # num_envs, an Env's follow its own stream)
                    np.testing.assert_array_equal(x, y, f"step {k}")
            same = same and not s[2].any()
            resets += int(np.count_nonzero(s[2]))
        self.assertFalse(same)
        self.assertGreater(resets, 3)

    def test_make_vec_builds_the_threaded_batch(self):
        # The ids' vector entry point is make_vec: asked for, and by default (Gymnasium's choice for
        # an id that has one); "sync" still vectorizes single environments.
        vec = self.gym.make_vec("roger/SG-DC2-v0", num_envs=4, vectorization_mode="vector_entry_point")
        self.assertIsInstance(vec, roger.VecEnv)
        self.assertEqual((vec.num_envs, vec.stage_info["context"], vec.spec.id), (4, "DC2", "roger/SG-DC2-v0"))
        self.assertIsInstance(self.gym.make_vec("roger/SG-DC2-v0", num_envs=2), roger.VecEnv)
        sync = self.gym.make_vec("roger/SG-DC2-v0", num_envs=2, vectorization_mode="sync")
        self.assertIsInstance(sync, self.gym.vector.SyncVectorEnv)
        stage = self.gym.make_vec("roger/Stage-v0", num_envs=2, vectorization_mode="vector_entry_point",
                                  curriculum=EXAMPLE, stage="Look", context="Gaze", threads=2,
                                  autoreset_mode="SameStep", timeout="truncate")
        self.assertEqual((stage.threads, stage.autoreset_mode.value, stage.timeout), (2, "SameStep", "truncate"))
        # max_episode_steps, which Gymnasium hands to a vector entry point (a TypeError before):
        # each episode truncated at its first decision, as with sync's TimeLimit.
        for mode in ("vector_entry_point", "sync"):
            capped = self.gym.make_vec("roger/Stage-v0", num_envs=2, vectorization_mode=mode, curriculum=EXAMPLE,
                                       stage="Look", context="Gaze", max_episode_steps=1)
            capped.reset(seed=4)
            self.assertEqual(capped.step(np.array([0, 0]))[3].tolist(), [True, True], mode)
        obs, info = vec.reset(seed=30)
        np.testing.assert_array_equal(info["seed"], [30, 31, 32, 33])
        self.assertTrue(vec.observation_space.contains(obs))

    def test_sync_vectorization_plays_distinct_worlds(self):
        # gymnasium.make_vec(..., "sync") seeds environment i with S + i and begins every later
        # episode with an unseeded reset: each environment's own stream keeps the worlds apart.
        sync = self.gym.make_vec("roger/Stage-v0", num_envs=4, vectorization_mode="sync", curriculum=EXAMPLE,
                                 stage="Look", context="Gaze")
        _, info = sync.reset(seed=500)
        sync.action_space.seed(7)
        worlds = set(int(s) for s in info["seed"])
        begun = 4
        for _ in range(400):
            _, _, terminated, truncated, info = sync.step(sync.action_space.sample())
            for i in np.flatnonzero(info.get("_seed", np.zeros(4, bool))):
                if info["ticks"][i] == 0:  # the first step of an episode (NEXT_STEP autoreset)
                    worlds.add(int(info["seed"][i]))
                    begun += 1
        print(f"SyncVectorEnv: {begun} episodes in {len(worlds)} distinct worlds")
        self.assertGreater(begun, 150)
        self.assertEqual(len(worlds), begun)
        # Unseeded from the start, the environments draw their streams apart, as Gymnasium's do.
        _, a = sync.reset()
        self.assertEqual(len(set(int(s) for s in a["seed"])), 4)

    def test_async_vectorization_of_a_made_environment(self):
        # AsyncVectorEnv pickles its factories into spawned processes: one that captures a made
        # environment needs it to pickle. (It closes the first environment a factory gives, to
        # read the spaces: a factory must not hand out the one object it captured, hence a copy.)
        env = roger.make(EXAMPLE, "Look", "Gaze")
        env.reset(seed=9)
        vec = self.gym.vector.AsyncVectorEnv([lambda: copy.deepcopy(env)] * 2, context="spawn")
        try:
            obs, info = vec.reset(seed=20)
            np.testing.assert_array_equal(info["seed"], [20, 21])
            single = roger.make(EXAMPLE, "Look", "Gaze")
            np.testing.assert_array_equal(obs[1], single.reset(seed=21)[0])
            obs, reward, terminated, truncated, info = vec.step(np.array([0, 1]))
            s_obs, s_reward, *_ = single.step(1)
            np.testing.assert_array_equal(obs[1], s_obs)
            self.assertEqual(reward[1], s_reward)
        finally:
            vec.close()

    def test_sync_vectorization_takes_every_seed(self):
        # Found by a probe: reset(seed=2**63) of a sync vector raised OverflowError, gathering
        # info["seed"] in an int64 array; as a numpy.uint64 it is gathered in a uint64 array.
        vec = self.gym.make_vec("roger/Stage-v0", 2, vectorization_mode="sync", curriculum=EXAMPLE, stage="Look",
                                context="Gaze")
        try:
            _, info = vec.reset(seed=2 ** 63)
            self.assertEqual(info["seed"].dtype, np.uint64)
            self.assertEqual(info["seed"].tolist(), [2 ** 63, 2 ** 63 + 1])
        finally:
            vec.close()

    def test_a_vector_environment_closing_a_captured_one_says_so(self):
        # Found by a probe: AsyncVectorEnv([lambda: env] * 2) closes env (the first a factory
        # returns) and the reset then said only "the environment is closed".
        env = roger.make(EXAMPLE, "Look", "Gaze")
        vec = self.gym.vector.AsyncVectorEnv([lambda: env] * 2, context="spawn")
        try:
            with self.assertRaises(roger.RogerError) as cm, self.warnings.catch_warnings():
                self.warnings.simplefilter("ignore")  # the workers' reports of the error
                vec.reset(seed=1)
            self.assertIn("a vector environment closed it", str(cm.exception))
            self.assertIn("copy.deepcopy(env)", str(cm.exception))
        finally:
            vec.close(terminate=True)
        with self.assertRaises(roger.RogerError) as cm:
            env.reset(seed=1)
        self.assertIn("a vector environment closed it", str(cm.exception))
        closed = roger.make(EXAMPLE, "Look", "Gaze")
        closed.close()  # closed by its user: no such hint
        with self.assertRaises(roger.RogerError) as cm:
            closed.reset(seed=1)
        self.assertNotIn("vector", str(cm.exception))

    def test_sync_vector_env_closing_a_captured_one_says_so(self):
        # Found by a probe: the hint after SyncVectorEnv.close() blamed AsyncVectorEnv.
        env = roger.make(EXAMPLE, "Look", "Gaze")
        vec = self.gym.vector.SyncVectorEnv([lambda: env, lambda: env])
        vec.reset(seed=0)
        vec.close()
        with self.assertRaises(roger.RogerError) as cm:
            env.reset(seed=0)
        self.assertIn("SyncVectorEnv.close() closed it: a vector environment's close() closes the environments it "
                      "holds", str(cm.exception))
        self.assertNotIn("AsyncVectorEnv", str(cm.exception))
        self.assertIn("copy.deepcopy(env)", str(cm.exception))
        with self.assertRaises(roger.RogerError) as cm:  # and in a copy
            copy.deepcopy(env).reset(seed=0)
        self.assertIn("SyncVectorEnv.close() closed it", str(cm.exception))

    def test_check_env_of_copies(self):
        from gymnasium.utils.env_checker import check_env
        env = self.gym.make("roger/SG-DC2-v0")
        env.reset(seed=4)
        env.step(0)
        check_env(copy.deepcopy(env).unwrapped, skip_render_check=True)


class StableBaselines3(unittest.TestCase):
    """Stable-Baselines3 on the registered ids, where it is importable (with torch): its env
    checker, make_vec_env's worlds, SubprocVecEnv over a made environment, its success logging,
    and docs/python.md's example (skipped elsewhere, and shown as skipped)."""

    def setUp(self):
        self.gym = require("gymnasium")
        self.sb3 = require("stable_baselines3")
        import torch
        torch.set_num_threads(1)

    def test_check_env(self):
        from stable_baselines3.common.env_checker import check_env
        check_env(self.gym.make("roger/SG-DC2-v0").unwrapped)
        check_env(self.gym.make("roger/SG-DC2-v0", mode="tick").unwrapped)

    def test_make_vec_env_plays_distinct_worlds(self):
        # make_vec_env seeds environment i with S + i once, then resets without a seed.
        from stable_baselines3.common.env_util import make_vec_env
        vec = make_vec_env("roger/Stage-v0", n_envs=4, seed=500,
                           env_kwargs={"curriculum": EXAMPLE, "stage": "Look", "context": "Gaze"})
        vec.reset()
        rng = np.random.default_rng(7)
        worlds, ended, successes = [], 0, []
        for _ in range(400):
            _, _, dones, infos = vec.step(rng.integers(0, 2, size=4))
            for done, info in zip(dones, infos):
                if done:
                    worlds.append(info["seed"])
                    successes.append(info["is_success"])
        print(f"make_vec_env: {len(worlds)} ended episodes in {len(set(worlds))} distinct worlds")
        self.assertGreater(len(worlds), 150)
        self.assertEqual(len(set(worlds)), len(worlds))
        self.assertTrue(any(successes) and not all(successes))

    def test_subproc_vec_env_over_a_made_environment(self):
        from stable_baselines3.common.vec_env import SubprocVecEnv
        env = self.gym.make("roger/Stage-v0", curriculum=EXAMPLE, stage="Look", context="Gaze")
        vec = SubprocVecEnv([lambda: env, lambda: env])  # the factories are pickled into the processes
        try:
            vec.seed(40)
            obs = vec.reset()
            single = roger.make(EXAMPLE, "Look", "Gaze")
            np.testing.assert_array_equal(obs[1], single.reset(seed=41)[0])
            vec.step(np.array([0, 1]))
        finally:
            vec.close()

    def test_eval_callback_logs_success(self):
        from stable_baselines3 import PPO
        from stable_baselines3.common.callbacks import EvalCallback
        from stable_baselines3.common.env_util import make_vec_env
        kwargs = {"curriculum": EXAMPLE, "stage": "Look", "context": "Gaze"}
        train = make_vec_env("roger/Stage-v0", n_envs=2, seed=1, env_kwargs=kwargs)
        evaluate = make_vec_env("roger/Stage-v0", n_envs=1, seed=1000000, env_kwargs=kwargs)
        callback = EvalCallback(evaluate, n_eval_episodes=4, eval_freq=64, log_path=os.path.join(WORK, "eval"))
        PPO("MlpPolicy", train, n_steps=64, batch_size=64, seed=1, device="cpu").learn(256, callback=callback)
        self.assertGreater(len(callback.evaluations_successes), 0)  # is_success read at each episode's end
        self.assertEqual(len(callback.evaluations_successes[0]), 4)

    def test_example(self):
        # docs/python.md, "With Stable-Baselines3": it runs, and asserts what it prints.
        r = subprocess.run([sys.executable, "docs/examples/sb3_example.py"], capture_output=True, text=True,
                           timeout=1200)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("held-out worlds", r.stdout)



def main():
    """unittest's main, with the exit code CTest reads: 1 when a test failed, 77 (skipped) when
    none failed but one was skipped for a missing tool, 0 when every test ran and passed."""
    try:
        result = unittest.main(verbosity=2, exit=False).result
    finally:
        if not os.environ.get("ROGER_TEST_WORK"):
            shutil.rmtree(WORK, ignore_errors=True)
    if not result.wasSuccessful() or result.testsRun == 0:
        return 1
    missing = sorted({reason for _, reason in result.skipped if reason.startswith(MISSING_TOOL)})
    if missing:
        print("SKIPPED: " + "; ".join(missing))
        return SKIP
    return 0


if __name__ == "__main__":
    sys.exit(main())
