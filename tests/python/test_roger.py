#!/usr/bin/env python3
"""test_roger.py: the Python module roger (CTest label `python`; docs/python.md).

    ROGER=build/engine/roger PYTHONPATH=build/python python3 tests/python/test_roger.py [-k NAME]

Run from the repository root. Needs numpy and the built module, never torch or gymnasium; where
gymnasium is importable, GymnasiumJudges also runs its env checker and vector wrappers on the
module (elsewhere it is skipped). Each class is one CTest test. Policies come from short `roger
train` runs, made once per process in ROGER_TEST_WORK (emptied first) or a temporary folder.
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
TIMEOUT_FAULT = "tests/python/fixtures/timeout_fault.lua"
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
        self.check(PAPER, t, "T", "DC6", skills={"Phi_SG": sg})


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
                np.testing.assert_array_equal(obs[i], row[0], where)
                self.assertEqual((rew[i], bool(term[i]), bool(trunc[i]), info["seed"][i]),
                                 (row[1], row[2], False, row[3]), where)
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

    def test_tick_mode_images_follow_the_body(self):
        # Eyes of 32 pixels (docs/scenarios.md, Bodies): the observations and their space say so.
        env = roger.make(EXAMPLE, stage="Look", context="Gaze", mode="tick", params={"eye_pixels": 32})
        self.assertEqual(env.observation_space["images"].shape, (2, 32, 3))
        obs, info = env.reset(seed=7)
        self.assertEqual(obs["images"].shape, (2, 32, 3))
        self.assertEqual(obs["stimulus"].shape, (2, 32))
        obs, reward, terminated, truncated, info = env.step(0)
        self.assertTrue(env.observation_space.contains(obs))

    def test_gymnasium_base_when_present(self):
        try:
            import gymnasium
        except ImportError:
            self.skipTest("gymnasium is not installed (the module does not need it)")
        self.assertIsInstance(roger.make(EXAMPLE, "Look", "Gaze"), gymnasium.Env)


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

    def test_unseeded_reset_goes_on(self):
        env = roger.make(EXAMPLE, "Look", "Gaze")
        env.reset(seed=123)
        _, info = env.reset()
        self.assertEqual(info["seed"], 124)
        env.reset(options={})  # options are accepted (the stage takes none)

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
        self.assertIsNone(roger.make(EXAMPLE, "Look", "Gaze").render())  # no render_mode: nothing
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
        obs, reward, terminated, truncated, info = vec.step(np.array([7]))  # out of range, yet ignored
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

    def test_reset_mask(self):
        vec, twin = self.make(), self.make()
        for v in (vec, twin):
            v.reset(seed=10)
            v.step(np.array([0, 0, 0]))
        mask = np.array([False, True, False])
        obs, info = vec.reset(seed=50, options={"reset_mask": mask})
        np.testing.assert_array_equal(info["_seed"], mask)
        self.assertEqual(info["seed"][1], 51)
        single = roger.make(EXAMPLE, "Look", "Gaze")
        np.testing.assert_array_equal(obs[1], single.reset(seed=51)[0])
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
        self.assertIsNone(self.make().render())

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

    def test_state_index_overflow(self):
        self.assertEqual(roger.state_index([2] * 19), 3 ** 19 - 1)
        self.assertRaisesWith(roger.RogerError, ["20 actions", "at most 19"], roger.state_index, [2] * 20)

    def test_policy_act_refuses_fractions(self):
        policy = roger.load_policy(train(EXAMPLE, "Look", "Gaze", 3, "look"))
        self.assertEqual(policy.act([2.0, 1.0]), policy.act([2, 1]))  # whole floats are the integers
        self.assertRaisesWith(roger.RogerError, ["integers 0 (NOREF)"], policy.act, [1.9, 0.7])
        self.assertRaisesWith(roger.RogerError, ["integers 0 (NOREF)"], policy.act, ["a", "b"])

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
        self.assertRaisesWith(roger.RogerError, ["call reset"], env.step, 0)  # the episode is over
        env.reset(seed=2)  # and the environment usable again


class GymnasiumJudges(unittest.TestCase):
    """Gymnasium's own checker and vector wrappers on the module, where gymnasium is importable
    (skipped elsewhere: the module does not need it)."""

    def setUp(self):
        try:
            import gymnasium
        except ImportError:
            self.skipTest("gymnasium is not installed")
        self.gym = gymnasium
        import warnings
        self.warnings = warnings

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
            if same:  # the same episodes until the first autoreset (then make_vec's seeds step by num_envs,
                for x, y in zip(s[:4], v[:4]):  # an Env's unseeded reset by one)
                    np.testing.assert_array_equal(x, y, f"step {k}")
            same = same and not s[2].any()
            resets += int(np.count_nonzero(s[2]))
        self.assertFalse(same)
        self.assertGreater(resets, 3)


if __name__ == "__main__":
    try:
        unittest.main(verbosity=2)
    finally:
        if not os.environ.get("ROGER_TEST_WORK"):
            shutil.rmtree(WORK, ignore_errors=True)
