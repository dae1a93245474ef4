"""roger: the stages of roger's curricula as Gymnasium-style environments.

    import roger
    env = roger.make("curricula/paper.lua", stage="T", context="B2")
    obs, info = env.reset(seed=1000000)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

One step is one decision of the stage's semi-MDP: the chosen action (an index of Psi, `env.actions`)
runs until the controller-state vector changes, through the engine's own episode loop. The
observation is that vector, one value per action: 0 NOREF, 1 !CONV, 2 CONV. `make(...,
mode="tick")` makes every control tick a decision and observes the raw senses too. `make_vec` steps
many worlds on C++ threads; `load_policy(path).act(obs)` is the greedy action of a policy.json
written by `roger train`. docs/python.md is the guide. The module needs numpy alone; when gymnasium
is importable, environments are `gymnasium.Env`s and the spaces are gymnasium's.
"""

import numbers

import numpy as np

from . import _roger
from ._roger import RogerError, ScriptError, mix, state_index

try:  # gymnasium is optional: its base class and spaces when present, the same shapes otherwise
    import gymnasium as _gym
    from gymnasium import spaces
    _EnvBase = _gym.Env
except ImportError:  # pragma: no cover - exercised where gymnasium is absent
    _gym = None
    from . import _spaces as spaces
    _EnvBase = object

__all__ = ["make", "make_vec", "load_policy", "Env", "VecEnv", "Policy", "RogerError", "ScriptError",
           "GAMMA_NAMES", "mix", "state_index", "spaces"]

GAMMA_NAMES = ("NOREF", "!CONV", "CONV")
_MODES = ("decision", "tick")


def _text_dict(d, what):
    if d is None:
        return {}
    if not isinstance(d, dict):
        raise RogerError(f"{what} must be a dict, got {type(d).__name__}")
    return {str(k): (str(v) if not isinstance(v, bool) else v) for k, v in d.items()}


def _seed(seed, what):
    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or not 0 <= int(seed) < 2**64:
        raise RogerError(f"{what}: a seed is an integer in [0, 2^64), got {seed!r}")
    return int(seed)


def _action(action, n, where):
    if isinstance(action, np.ndarray) and action.shape == ():
        action = action.item()
    if isinstance(action, bool) or not isinstance(action, numbers.Integral):
        raise RogerError(f"{where}: an action is an integer index of Psi in [0, {n}), got {action!r}")
    if not 0 <= int(action) < n:
        raise RogerError(f"{where}: action index {int(action)} is not in [0, {n})")
    return int(action)


def _state_space(n):
    return spaces.MultiDiscrete(np.full(n, 3, dtype=np.int64))


class Env(_EnvBase):
    """One stage and context of a curriculum as an environment (see the module's doc)."""

    metadata = {"render_modes": []}

    def __init__(self, curriculum, stage, context, params=None, skills=None, scenario=None, mode="decision"):
        if mode not in _MODES:
            raise RogerError(f"make: mode must be one of {_MODES}, got {mode!r}")
        self._env = _roger.Environment(str(curriculum), str(stage), str(context), scenario or "",
                                       _text_dict(params, "params"), _text_dict(skills, "skills"), mode == "tick")
        self.stage_info = self._env.info
        self.actions = tuple(self.stage_info["actions"])
        self.mode = mode
        self.action_space = spaces.Discrete(len(self.actions))
        state = _state_space(len(self.actions))
        if mode == "tick":
            self.observation_space = spaces.Dict({
                "state": state,
                "images": spaces.Box(0, 255, (2, 128, 3), np.uint8),
                "stimulus": spaces.Box(0.0, 1.0, (2, 128), np.float32),
                "touch": spaces.Box(-np.inf, np.inf, (3, 5), np.float32),
                "joints": spaces.Box(-np.inf, np.inf, (8,), np.float64),
                "joint_velocities": spaces.Box(-np.inf, np.inf, (8,), np.float64),
            })
        else:
            self.observation_space = state
        self._next_seed = 0

    def __repr__(self):
        i = self.stage_info
        return f"<roger.Env {i['curriculum']} stage {i['stage']} context {i['context']} ({self.mode})>"

    def _observe(self, state):
        state = state.astype(np.int64)
        if self.mode != "tick":
            return state
        obs = self._env.senses()
        obs["state"] = state
        return obs

    def _info(self, state, ended=False):
        e = self._env
        info = {"sim_seconds": e.sim_seconds, "ticks": e.ticks, "decisions": e.decisions, "seed": e.seed,
                "state": {a: GAMMA_NAMES[g] for a, g in zip(self.actions, state)}}
        if ended:
            info["episode_reward"] = e.episode_reward
            info["success"] = e.success
        return info

    def reset(self, *, seed=None, options=None):
        """Starts the episode in the world of `seed` (roger eval's --seed); without one, the seed
        after the last episode's (0 first). Returns (observation, info)."""
        if _gym is not None:
            super().reset(seed=seed)
        seed = self._next_seed if seed is None else _seed(seed, "reset")
        state, running = self._env.reset(seed)
        self._next_seed = (seed + 1) % 2**64
        if not running:
            raise RogerError(f"reset: the episode of seed {seed} ended before its first decision "
                             "(its absorbing function holds at once)")
        return self._observe(state), self._info(state)

    def step(self, action):
        """Runs one decision: `action` until the next decision point (the state changes, or the
        action gives up). Returns (observation, reward, terminated, truncated, info); truncated
        is the time limit."""
        a = _action(action, len(self.actions), f"step ({self.stage_info['stage']}/{self.stage_info['context']})")
        state, reward, terminated, truncated = self._env.step(a)
        return self._observe(state), reward, terminated, truncated, self._info(state, terminated or truncated)

    def close(self):
        self._env = None


class VecEnv:
    """num_envs environments of one stage, stepped together on C++ threads with the GIL released.

    Environment i's k-th episode runs in the world of seed + i + k * num_envs; an environment whose
    episode ends is reset at once (its step returns the new episode's first observation, the last
    one in info["final_observation"]). Results depend on the seeds and actions only, never on the
    thread count."""

    def __init__(self, curriculum, stage, context, num_envs, threads=None, params=None, skills=None, scenario=None):
        if isinstance(num_envs, bool) or not isinstance(num_envs, numbers.Integral) or num_envs < 1:
            raise RogerError(f"make_vec: num_envs must be a positive integer, got {num_envs!r}")
        if threads is None:
            import os
            threads = min(int(num_envs), len(os.sched_getaffinity(0)))
        self._vec = _roger.VecEnvironment(str(curriculum), str(stage), str(context), scenario or "",
                                          _text_dict(params, "params"), _text_dict(skills, "skills"),
                                          int(num_envs), int(threads))
        self.stage_info = self._vec.info
        self.actions = tuple(self.stage_info["actions"])
        self.num_envs = int(num_envs)
        self.threads = self._vec.threads
        self.single_action_space = spaces.Discrete(len(self.actions))
        self.single_observation_space = _state_space(len(self.actions))
        self.action_space = spaces.MultiDiscrete(np.full(self.num_envs, len(self.actions), dtype=np.int64))
        self.observation_space = spaces.MultiDiscrete(np.full((self.num_envs, len(self.actions)), 3, dtype=np.int64))

    def reset(self, *, seed=0, options=None):
        """Resets every environment; returns (observations [num_envs, |Psi|], info)."""
        states, seeds = self._vec.reset(_seed(seed, "reset"))
        return states.astype(np.int64), {"seed": seeds}

    def step(self, actions):
        """Steps every environment with its action; returns numpy arrays (observations, rewards,
        terminated, truncated) and info with the ended episodes' final_observation, episode_seed,
        episode_sim_s, episode_ticks, episode_reward and a boolean mask `_episode`."""
        a = np.asarray(actions)
        if a.shape != (self.num_envs,) or not np.issubdtype(a.dtype, np.integer):
            raise RogerError(f"step: expected {self.num_envs} integer actions, got {a.dtype} array of shape {a.shape}")
        r = self._vec.step(a.astype(np.int64))
        ended = r["terminated"] | r["truncated"]
        info = {"seed": r["seeds"], "final_observation": r["final_states"].astype(np.int64), "_episode": ended,
                "episode_seed": r["episode_seeds"], "episode_sim_s": r["episode_sim_s"],
                "episode_ticks": r["episode_ticks"], "episode_reward": r["episode_rewards"]}
        return r["states"].astype(np.int64), r["rewards"], r["terminated"], r["truncated"], info

    def close(self):
        self._vec = None


class Policy:
    """A policy.json written by `roger train`: act(obs) is the action `roger eval` takes."""

    def __init__(self, path):
        self._p = _roger.Policy(str(path))
        self.path = str(path)
        self.actions = tuple(self._p.actions)
        self.stage, self.context, self.seed = self._p.stage, self._p.context, self._p.seed

    def act(self, obs):
        """The greedy action (QTable::policy_action) of a controller-state vector."""
        return self._p.act(np.asarray(obs, dtype=np.int64))

    @property
    def q(self):
        """The Q table, one row per state (state_index(obs)), one column per action."""
        return self._p.q

    def __repr__(self):
        return f"<roger.Policy {self.path}: stage {self.stage} context {self.context}, actions {self.actions}>"


def make(curriculum, stage, context, params=None, skills=None, scenario=None, mode="decision"):
    """An environment of `stage` in `context` of a curriculum (a path or a bare name: "paper").

    params: scenario parameters over the stage's ({"shape": "spade"}, as --set); skills: each
    learned skill the context uses, {"Phi_SG": "out/sg/policy.json"} (as --skill); scenario:
    another scenario than the stage's; mode: "decision" (semi-MDP) or "tick" (every control tick,
    raw senses in a Dict observation)."""
    return Env(curriculum, stage, context, params=params, skills=skills, scenario=scenario, mode=mode)


def make_vec(curriculum, stage, context, num_envs, threads=None, params=None, skills=None, scenario=None):
    """num_envs environments stepped together in C++ threads (VecEnv); threads defaults to
    min(num_envs, the cores this process may use)."""
    return VecEnv(curriculum, stage, context, num_envs, threads=threads, params=params, skills=skills,
                  scenario=scenario)


def load_policy(path):
    """A saved policy.json (Policy); raises RogerError naming the file and field when malformed."""
    return Policy(path)
