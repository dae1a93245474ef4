"""roger: the stages of roger's curricula as Gymnasium 1.x environments.

    import roger
    env = roger.make("curricula/paper.lua", stage="T", context="B2")
    obs, info = env.reset(seed=1000000)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

One step is one decision of the stage's semi-MDP: the chosen action (an index of Psi, `env.actions`)
runs until the controller-state vector changes, through the engine's own episode loop. The
observation is that vector, one value per action: 0 NOREF, 1 !CONV, 2 CONV. The stage's time-out
is terminal (terminated, info["time_out"]), as for the engine's learner (timeout="truncate"
reports it as truncated). An unseeded reset plays the next world of the environment's own
stream, so environments seeded S, S + 1, ... never share worlds. `make(..., mode="tick")` makes
every control tick a decision and observes the raw senses too; `render_mode="rgb_array"` draws
what `roger render` draws. A stage's task space is env.task_space (a Dict space):
reset(options={"task": {...}}) plays a task of it, and resets without one take the stage's
teacher's (make(..., tasks=..., teacher=...) gives others). `make_vec` steps many worlds on C++
threads; `load_policy(path).act(obs)` is the greedy action of a policy.json written by `roger
train`, and `load_policy(path).make()` the environment `roger eval --policy` plays it in (the
trial's own parameters and learned skills). Environments pickle and
deep-copy. docs/python.md is the guide. The module needs numpy alone; when gymnasium is
importable, environments are `gymnasium.Env`s, `make_vec` a `gymnasium.vector.VectorEnv`, the
spaces are gymnasium's and the ids roger/SG-B1-v0 ... roger/T-DC6-v0 and roger/Stage-v0 are
registered, each with make_vec as its vector entry point.
"""

import bisect
import contextlib
import copy
import numbers
import os
import secrets
import threading
import warnings

import numpy as np

from . import _roger
from ._roger import PlacementError, RogerError, ScriptError, __version__, project_folder

try:  # gymnasium is optional: its base classes and spaces when present, the same contracts otherwise
    import gymnasium as _gym
    from gymnasium import spaces
    from gymnasium.vector.utils import batch_space as _batch_space
    try:
        from gymnasium.vector import AutoresetMode
    except ImportError:  # gymnasium 1.0 names no modes: it autoresets at the next step only
        from ._base import AutoresetMode
    _EnvBase, _VecBase = _gym.Env, _gym.vector.VectorEnv
except ImportError:  # exercised where gymnasium is absent
    _gym = None
    from . import _spaces as spaces
    from ._base import AutoresetMode
    from ._base import Env as _EnvBase, VectorEnv as _VecBase
    _batch_space = None

__all__ = ["make", "make_vec", "load_policy", "Env", "VecEnv", "Policy", "RogerError", "ScriptError", "PlacementError",
           "RogerWarning", "AutoresetMode", "GAMMA_NAMES", "PAPER_IDS", "mix", "state_index", "spaces", "project_folder",
           "axis", "Axis"]


def __dir__():
    """The module's names as a user sees them (dir(roger), a shell's completion): the public ones and
    the dunders, not the modules it imports for itself (found by a probe: np, os, copy, ... were
    listed as if they were roger's)."""
    return sorted(set(__all__) | {n for n in globals() if n.startswith("__")})


class RogerWarning(UserWarning):
    """What roger notes beside a result without refusing it, as the command line's "note" lines: a
    saved policy played in a curriculum other than the one it trained with, or in its own changed
    since (`warnings.simplefilter("error", roger.RogerWarning)` makes it an error)."""


def _warn(message):
    """Warns (RogerWarning) at the user's line: the first frame outside this package."""
    import sys
    import warnings
    here = os.path.dirname(os.path.abspath(__file__))
    level, frame = 1, sys._getframe(1)
    while frame is not None and os.path.dirname(os.path.abspath(frame.f_code.co_filename)) == here:
        level, frame = level + 1, frame.f_back
    warnings.warn(message, RogerWarning, stacklevel=level + 1)


GAMMA_NAMES = ("NOREF", "!CONV", "CONV")
_MODES = ("decision", "tick")
_TIMEOUTS = ("terminate", "truncate")
_RENDER_MODES = ["rgb_array"]
_DECISION_FPS = 4  # frames per second of a video of decisions (a decision lasts about 0.1 to 1 s)


# What a value of make's params or skills is, for the message that refuses None.
_VALUE_OF = {"params": "a number, a string or a bool", "skills": "the path of a policy.json (or a roger.Policy)"}


def _text_dict(d, what):
    if d is None:
        return {}
    if not isinstance(d, dict):
        raise RogerError(f"{what} must be a dict, got {type(d).__name__}")
    for k, v in d.items():
        if v is None:  # found by a probe: str(None) was taken as the text 'None' (params: "got 'None'")
            raise RogerError(f"{what}[{k!r}] is None, which is no value: give {_VALUE_OF.get(what, 'a value')}")
    return {str(k): _param_value(v) if what == "params" else (str(v) if not isinstance(v, bool) else v)
            for k, v in d.items()}


def _param_value(v):
    """A value of make's params as the engine takes it: a list parameter's list or tuple as the
    comma-separated text --set takes (found by a probe: ['left_eye', 'right_eye'] reached the
    scenario as its repr, which it refused)."""
    if isinstance(v, bool):
        return v
    if isinstance(v, (list, tuple)):
        return ",".join(str(x) for x in v)
    return str(v)


def _seed(seed, what):
    if isinstance(seed, np.integer):
        seed = int(seed)
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


def _tag(i):
    """mix's second argument: an integer, or a tag of 1 to 8 ASCII characters read as the integer of
    its bytes (the first the most significant), as the engine writes its streams' tags: "teach" is
    0x7465616368, the teacher's stream of roger train."""
    if isinstance(i, str):
        if not 1 <= len(i) <= 8 or not i.isascii():
            raise RogerError(f"mix: a tag is 1 to 8 ASCII characters (\"teach\"), got {i!r}")
        return int.from_bytes(i.encode("ascii"), "big")
    return _seed(i, "mix (its second argument)")


def mix(seed, i):
    """The seed mixer of the engine: roger train's training episode e runs in world mix(seed, e + 1),
    and its teacher draws from mix(seed, "teach"). `i` is an integer in [0, 2^64) or a tag of 1 to
    8 ASCII characters, the integer of its bytes as the engine writes it ("teach" = 0x7465616368)."""
    return _roger.mix(_seed(seed, "mix"), _tag(i))


def _holds_bool(obs):
    """Whether a state vector holds a boolean, which numpy would read as 0 or 1 beside integers."""
    return isinstance(obs, (list, tuple)) and any(isinstance(x, (bool, np.bool_)) for x in obs)


def _refuse_tick_observation(obs, where, expected):
    """A tick mode observation (a dict of the senses and the state) given where its state vector is
    meant: refused in a line, naming the key to pass, rather than with the repr of its images."""
    if isinstance(obs, dict):
        keys = ", ".join(repr(k) for k in obs)
        raise RogerError(f"{where}: takes {expected}, got a dict ({keys}), a tick mode observation: "
                         "pass its controller states, obs['state']")


def _short(obs):
    """A value as a message shows it: its repr, cut short (a big array's is thousands of characters)."""
    if isinstance(obs, int) and obs.bit_length() > 1000:  # repr refuses an int of over 4300 digits
        return f"an integer of {obs.bit_length()} bits"
    text = repr(obs)
    if len(text) <= 120:
        return text
    shape = f" of shape {obs.shape}" if isinstance(obs, np.ndarray) else ""
    return f"{text[:100]}... (a {type(obs).__name__}{shape})"


def state_index(obs):
    """The row of a policy's Q table for a state vector (first action most significant): the integers
    0 (NOREF), 1 (!CONV), 2 (CONV), as Policy.act takes them (floats only when whole numbers;
    booleans are not states)."""
    _refuse_tick_observation(obs, "state_index", "a state vector of the integers 0 (NOREF), 1 (!CONV), 2 (CONV)")
    o = np.asarray(obs)
    if (o.ndim != 1 or o.dtype.kind not in "iuf" or (o.dtype.kind == "f" and not np.array_equal(o, np.trunc(o)))
            or _holds_bool(obs)):
        raise RogerError(f"state_index: a state is a vector of the integers 0 (NOREF), 1 (!CONV), 2 (CONV), "
                         f"got {_short(obs)}")
    if o.size == 0:  # a stage has at least one action: an empty vector is no state (it would be row 0)
        raise RogerError("state_index: a state has one value per action, got an empty vector")
    bad = o[(o < 0) | (o > 2)]
    if bad.size:  # here, not in the extension: a value past its int would be a TypeError there
        raise RogerError(f"state_index: a controller state is 0, 1 or 2, got {bad[0]}")
    return _roger.state_index(o.astype(np.int64).tolist())


def _names(curriculum, stage, context, where):
    """make's (make_vec's) curriculum, stage and context, refused when not text: str(None) would be
    looked up as a stage named 'None'."""
    if not isinstance(curriculum, (str, os.PathLike)):
        raise RogerError(f"{where}: curriculum must be a path or a bare name (a str, 'paper'), "
                         f"got {type(curriculum).__name__} {curriculum!r}")
    for name, value in (("stage", stage), ("context", context)):
        if not isinstance(value, str):
            raise RogerError(f"{where}: {name} must be a str naming a {name} of the curriculum, "
                             f"got {type(value).__name__} {value!r}")


def _warn_no_render_mode(maker):
    # As Gymnasium's own environments do (found by a probe: a None, unsaid, read as a bug).
    warnings.warn(f"render: this environment draws nothing (render_mode is None); make it with "
                  f"{maker}(..., render_mode='rgb_array') to get images", UserWarning, stacklevel=3)


def _render_mode(render_mode, where):
    if render_mode is not None and render_mode not in _RENDER_MODES:
        raise RogerError(f"{where}: render_mode must be None or one of {_RENDER_MODES}, got {render_mode!r}")
    return render_mode


def _render_width(width, where):
    if isinstance(width, bool) or not isinstance(width, numbers.Integral) or not 100 <= width <= 16000:
        raise RogerError(f"{where}: render_width is an integer number of pixels in [100, 16000], got {width!r}")
    return int(width)


def _positive_integer(value):
    """An integer of at least 1 (a bool is no count: True would be 1 thread)."""
    return not isinstance(value, bool) and isinstance(value, numbers.Integral) and value >= 1


def _state_space(n):
    return spaces.MultiDiscrete(np.full(n, 3, dtype=np.int64))


def _options(options, where, known):
    """reset's options as a dict, refusing keys nothing reads (a typo would be ignored silently)."""
    if options is not None and not isinstance(options, dict):
        raise RogerError(f"{where}: options must be a dict or None, got {type(options).__name__}")
    options = dict(options or {})
    unknown = sorted(str(k) for k in options if k not in known)
    if unknown:
        knows = ", ".join(repr(k) for k in known) if known else "none"
        raise RogerError(f"{where}: unknown option {', '.join(repr(k) for k in unknown)} "
                         f"(the known options: {knows})")
    return options


def _timeout(timeout, where):
    if timeout not in _TIMEOUTS:
        raise RogerError(f"{where}: timeout must be one of {_TIMEOUTS}, got {timeout!r}")
    return timeout

# ---- tasks and teachers (docs/python.md, "Tasks and teachers")

_TEACH = 0x7465616368  # "teach": the teacher's stream of a seed, as roger train's trial draws it
_MAX_SKIPPED_IN_A_ROW = 100  # a teacher's tasks the scenario cannot place, in a row, before a reset gives up (roger train's)
_SKIPS_PER_WORLD = 10  # skips in one world seed before the draws move to another (roger train's)


class Axis:
    """An axis of a task space (roger.axis.int, .real, .choice), as Lua text."""

    def __init__(self, lua):
        self.lua = lua

    def __repr__(self):
        return self.lua


def _lua_number(x, what, kind="a bound"):
    if isinstance(x, np.generic):
        x = x.item()
    if isinstance(x, bool) or not isinstance(x, numbers.Real):
        raise RogerError(f"{what}: {kind} is a finite number, got {x!r}")
    if isinstance(x, numbers.Integral):  # Lua's integers are 64-bit (np.isfinite cannot take a larger int)
        if not -2**63 <= x < 2**63:
            raise RogerError(f"{what}: {kind} is a finite number, an integer within Lua's 64-bit integers, got {x!r}")
        return str(x)
    if not np.isfinite(float(x)):
        raise RogerError(f"{what}: {kind} is a finite number, got {x!r}")
    return repr(float(x))


def _lua_value(v, what):
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return '"' + "".join(c if c.isprintable() and c not in '"\\' else f"\\{ord(c):03d}" for c in v) + '"'
    if not isinstance(v, numbers.Real):  # found by a probe: choice([None, 1]) said "a bound is a finite number"
        raise RogerError(f"{what}: a value is a string, a finite number or a bool, got {type(v).__name__} {v!r}")
    return _lua_number(v, what, "a value")


class axis:
    """The axes of a task space, named as in Lua (roger.int, roger.real, roger.choice):
    make(..., tasks={"obstacles": roger.axis.int(0, 6), "shape": roger.axis.choice(["circle", "spade"])})."""

    @staticmethod
    def int(lo, hi):
        """An integer axis lo..hi inclusive: in task_space, Discrete(hi - lo + 1, start=lo)."""
        a, b = _lua_number(lo, "roger.axis.int"), _lua_number(hi, "roger.axis.int")
        # Checked here, in the Lua side's words (roger.int), not first at make.
        for name, x in (("lo", lo), ("hi", hi)):
            if float(x) != np.floor(float(x)):
                raise RogerError(f"roger.axis.int(lo, hi): {name} must be an integer, got {x!r}")
        if float(lo) >= float(hi):
            how = "a single value" if float(lo) == float(hi) else "reversed"
            raise RogerError(f"roger.axis.int({a}, {b}): the range is {how} (lo must be below hi; a single value "
                             "needs no axis)")
        return Axis(f"roger.int({a}, {b})")

    @staticmethod
    def real(lo, hi):
        """A real axis [lo, hi]: in task_space, Box(lo, hi, shape=(), dtype=float64)."""
        a, b = _lua_number(lo, "roger.axis.real"), _lua_number(hi, "roger.axis.real")
        if float(lo) >= float(hi):
            how = "a single value" if float(lo) == float(hi) else "reversed"
            raise RogerError(f"roger.axis.real({a}, {b}): the range is {how} (lo must be below hi; a single value "
                             "needs no axis)")
        return Axis(f"roger.real({a}, {b})")

    @staticmethod
    def choice(values):
        """A choice among values (strings, numbers, booleans): in task_space, Discrete(len(values))
        over their indices."""
        if isinstance(values, (str, bytes)) or not hasattr(values, "__iter__"):
            raise RogerError(f"roger.axis.choice: expects a list of values, got {values!r}")
        texts = [_lua_value(v, "roger.axis.choice") for v in values]
        lua = "roger.choice{" + ", ".join(texts) + "}"
        # Checked here, in the Lua side's words (roger.choice), not first at make. A scenario reads
        # each value as text: 1 and "1" are the same value.
        seen = set()
        for text in texts:
            value = text[1:-1] if text.startswith('"') else text
            if value in seen:
                raise RogerError(f"{lua}: the value '{value}' is listed twice")
            seen.add(value)
        if len(texts) < 2:
            how = "the list is empty" if not texts else "a single value needs no axis (give it in params)"
            raise RogerError(f"{lua}: {how}; a choice is among at least two values")
        return Axis(lua)


def _tasks_source(tasks):
    """make's tasks as the Lua text of the stage field: a dict {parameter: Axis or Lua text}, or
    the text of the whole table; "" for the stage's own."""
    if tasks is None:
        return ""
    if isinstance(tasks, str):
        return tasks
    if not isinstance(tasks, dict) or not tasks:
        raise RogerError(f"make: tasks must be a non-empty dict {{parameter: roger.axis.int(lo, hi) | "
                         f"roger.axis.real(lo, hi) | roger.axis.choice([...])}} or Lua text, got {tasks!r}")
    parts = []
    for k, v in tasks.items():
        if not isinstance(k, str):
            raise RogerError(f"make: tasks' keys are scenario parameters (strings), got {k!r}")
        if not isinstance(v, (Axis, str)):
            raise RogerError(f"make: tasks[{k!r}] must be roger.axis.int(lo, hi), .real(lo, hi), .choice([...]) "
                             f"or Lua text such as 'roger.int(0, 6)', got {v!r}")
        parts.append(f"[{_lua_value(k, 'tasks')}] = {v.lua if isinstance(v, Axis) else v}")
    return "{" + ", ".join(parts) + "}"


def _teacher_source(teacher):
    """make's teacher as (Lua text, Lua file, teaches): None the stage's, False none, a path to a
    .lua file that returns a teacher, or Lua text (roger.teacher.alp_gmm{...}, function(history, rng)
    ... end)."""
    if teacher is None:
        return "", "", True
    if teacher is False:
        return "", "", False
    if not isinstance(teacher, str) or not teacher.strip():
        raise RogerError("make: teacher must be None (the stage's), False (none), Lua text such as "
                         f"'roger.teacher.alp_gmm{{}}' or a .lua file that returns a teacher, got {teacher!r}")
    import os
    if os.path.isfile(teacher):
        return "", teacher, True
    if teacher.strip().endswith(".lua") and "\n" not in teacher and "{" not in teacher and "(" not in teacher:
        raise RogerError(f"make: teacher names no file: {teacher}")
    return teacher, "", True


def _task_space(dims):
    """The Gymnasium Dict space of the task dimensions the extension lists (None when none)."""
    if not dims:
        return None
    axes = {}
    for d in dims:
        if d["kind"] == "int":
            axes[d["name"]] = spaces.Discrete(round(d["high"] - d["low"]) + 1, start=round(d["low"]))
        elif d["kind"] == "real":
            axes[d["name"]] = spaces.Box(d["low"], d["high"], (), np.float64)
        else:
            axes[d["name"]] = spaces.Discrete(len(d["choices"]))
    return spaces.Dict(axes)


def _skill_paths(skills):
    """make's skills with each loaded Policy given as its file's path, as policy= takes one, and
    each os.PathLike as its text."""
    if not isinstance(skills, dict):
        return skills
    return {k: v.path if isinstance(v, Policy) else _path_text(v) for k, v in skills.items()}


def _native(text):
    """Text for the engine: a str that holds bytes of a file name that are not UTF-8 (as os.fsdecode
    and os.listdir give them, surrogates) as those very bytes, which the engine takes as the
    command line does; any other value as str(value) (found by a probe: such a name raised a
    binding's TypeError, where `roger eval` read the file)."""
    if not isinstance(text, (str, bytes)):
        text = os.fspath(text) if isinstance(text, os.PathLike) else str(text)
    if isinstance(text, str):
        try:
            text.encode("utf-8")
        except UnicodeEncodeError:
            return os.fsencode(text)
    return text


def _path_text(value):
    """A pathlib.Path (any os.PathLike) as its text, which every file argument takes; else the value
    as given. The arguments are kept as text, so that a copy makes them absolute (_recipe) and the
    spec writes them (spec.to_json)."""
    return os.fspath(value) if isinstance(value, os.PathLike) else value


def _tasks_text(tasks):
    """make's tasks with each axis as its Lua text, which make takes alike: what the spec keeps, so
    that spec.to_json() writes it and spec.make() builds the same task space."""
    if not isinstance(tasks, dict):
        return tasks
    return {k: v.lua if isinstance(v, Axis) else v for k, v in tasks.items()}


def _absolute(path):
    """A path argument as a copy re-creates it: absolute when it names a file from here (a copy may
    be made in another working directory: a SubprocVecEnv's or AsyncVectorEnv's worker, or after
    os.chdir), else as given (a bare name such as "paper", resolved in the project from anywhere)."""
    return os.path.abspath(path) if isinstance(path, (str, os.PathLike)) and os.path.isfile(path) else path


def _recipe(init):
    """make's (or make_vec's) arguments with every path absolute: what a copy is made with. The
    arguments as typed stay the environment's own (its spec, its stage_info)."""
    recipe = dict(init)
    for key in ("curriculum", "policy", "scenario", "teacher"):
        if isinstance(recipe.get(key), str):
            recipe[key] = _absolute(recipe[key])
    if isinstance(recipe.get("skills"), dict):
        recipe["skills"] = {k: _absolute(v) for k, v in recipe["skills"].items()}
    return recipe


class _Copyable:
    """Pickling and deepcopy by the construction arguments and what continues the same worlds:
    a copy is a new environment made with the same arguments (its files by their absolute paths,
    so that it is made alike from another working directory), given the same seed stream and
    np_random, whose running episode is replayed from its seed and actions (an episode is a
    function of them), so it continues exactly where the original is."""

    # The spaces a copy takes over from the original, generators and all.
    _SPACES = ("action_space", "observation_space", "single_action_space", "single_observation_space", "task_space")

    # What a call meets when another thread's call holds the environment (_using).
    _SHARED = ("the environment is being used by another thread at the same time: one environment is not shared "
               "between threads; make one environment per thread (or one make_vec batch)")

    def __getstate__(self):
        with self._using("copy"):
            closed = self._closed_now()
            return {"init": dict(self._init), "recipe": dict(self._recipe), "what": repr(self),
                    "stage_info": self._stage_info, "spec": self.spec, "closed": closed,
                    "closed_by_vector": getattr(self, "_closed_by_vector", False),
                    "np_random": (self._np_random, self._np_random_seed),
                    "spaces": {name: getattr(self, name) for name in self._SPACES if getattr(self, name, None) is not None},
                    "state": None if closed else self._state()}

    def __setstate__(self, state):
        try:
            self.__init__(**state.get("recipe", state["init"]))
        except RogerError as e:
            raise _again(e, f"copy: could not re-create the copy of {state.get('what', 'an environment')} (a copy "
                            f"is a new environment made with the same arguments): {e}") from e
        # What the original shows (the arguments as typed) stays what the copy shows.
        self._init = dict(state["init"])
        self._stage_info = state.get("stage_info", self._stage_info)
        self.spec = state["spec"]
        self._np_random, self._np_random_seed = state["np_random"]
        # The spaces as they were, their generators too (a seeded task_space's sample_tasks, an
        # action_space's sample() go on alike), as a deepcopy of Gymnasium's own environments has them.
        for name, space in state.get("spaces", {}).items():
            setattr(self, name, space)
        if state["closed"]:
            self.close()
            self._closed_by_vector = state.get("closed_by_vector", False)
        else:
            self._restore(state["state"])

    @property
    def stage_info(self):
        """The stage as the engine trains it (docs/python.md): a fresh copy at each read, so that an
        edit, which the environment would never read, does not seem to stick."""
        return copy.deepcopy(self._stage_info)

    @contextlib.contextmanager
    def _using(self, what):
        """Holds the environment for `what` (reset, step...): a call of another thread meanwhile is
        refused rather than interleaved, and close() waits for it to end."""
        lock = self.__dict__.get("_lock")
        if lock is None:  # an environment whose __init__ failed early holds nothing to guard
            yield
            return
        # A close() from another thread holds it only to close: wait for it, and meet the closed environment.
        if not lock.acquire(blocking=False) and not (self.__dict__.get("_closing") and lock.acquire()):
            raise RogerError(f"{what}: {self._SHARED}")
        try:
            yield
        finally:
            lock.release()


def _again(error, message):
    """`error` raised anew with `message`: the same class (RogerError, ScriptError, PlacementError)
    and the same attributes (.file, .line, .env...)."""
    again = type(error)(message)
    for key, value in vars(error).items():
        setattr(again, key, value)
    return again


def _called_from_a_vector_env():
    """The class of gymnasium's vector environment whose code (through wrappers) called close, or
    False: AsyncVectorEnv closes a factory's first environment, which a factory that returns a
    captured environment hands on; any vector environment's close() closes those it holds."""
    import sys
    frame, found = sys._getframe(2), False
    for _ in range(12):
        if frame is None:
            break
        if str(frame.f_globals.get("__name__", "")).startswith("gymnasium.vector"):
            found = True  # a comprehension's frame has no self: the method's, further out, has
            owner = frame.f_locals.get("self")
            if owner is not None:
                return type(owner).__name__
        frame = frame.f_back
    return "a vector environment" if found else False


def _closed_by_vector_hint(vector):
    """Why a vector environment closed an environment, as `vector` (its class's name) does it."""
    remedy = ("give it a factory that makes a new environment, or returns copy.deepcopy(env)")
    if vector == "AsyncVectorEnv" or vector is True:  # True: a pickle of a version that named no class
        return (": a vector environment closed it (gymnasium's AsyncVectorEnv closes the first environment a "
                f"factory returns, after reading its spaces): {remedy}")
    who = "a vector environment's close()" if vector == "a vector environment" else f"{vector}.close()"
    return (f": {who} closed it: a vector environment's close() closes the environments it holds, "
            f"and its factories returned this one (captured, lambda: env) rather than a new one: {remedy}")


class Env(_Copyable, _EnvBase):
    """One stage and context of a curriculum as an environment (see the module's doc)."""

    metadata = {"render_modes": _RENDER_MODES, "render_fps": _DECISION_FPS}
    _closed_by_vector = False
    _spec = None

    @property
    def spec(self):
        """Gymnasium's EnvSpec of this environment (None without gymnasium)."""
        return self._spec

    @spec.setter
    def spec(self, value):
        # Kept with each axis of its tasks as Lua text and each Policy as its path, which make takes
        # alike: gymnasium.make sets the spec with the arguments as given, and one holding an Axis
        # or a Policy did not write to JSON (found by a probe: spec.to_json() raised TypeError).
        kwargs = getattr(value, "kwargs", None)
        if isinstance(kwargs, dict):
            k = dict(kwargs)
            if "tasks" in k:
                k["tasks"] = _tasks_text(k["tasks"])
            if isinstance(k.get("policy"), Policy):
                k["policy"] = k["policy"].path
            if isinstance(k.get("skills"), dict):
                k["skills"] = _skill_paths(k["skills"])
            value = copy.copy(value)  # the caller's spec keeps its own arguments
            value.kwargs = k
        self._spec = value

    def __init__(self, curriculum, stage, context, params=None, skills=None, scenario=None, mode="decision",
                 render_mode=None, render_width=1000, timeout="terminate", tasks=None, teacher=None, policy=None):
        self._lock = threading.RLock()  # held by reset, step, render and copies; close waits for it
        if mode not in _MODES:
            raise RogerError(f"make: mode must be one of {_MODES}, got {mode!r}")
        if isinstance(policy, Policy):
            policy = policy.path
        curriculum, scenario, teacher, policy = map(_path_text, (curriculum, scenario, teacher, policy))
        skills = _skill_paths(skills)
        self._init = {"curriculum": curriculum, "stage": stage, "context": context, "params": params,
                      "skills": skills, "scenario": scenario, "mode": mode, "render_mode": render_mode,
                      "render_width": render_width, "timeout": timeout, "tasks": tasks, "teacher": teacher}
        self._init["policy"] = policy
        self._recipe = _recipe(self._init)
        _names(curriculum, stage, context, "make")
        params, embedded, played = _with_policy(policy, curriculum, stage, context, params, scenario, "make")
        self.render_mode = _render_mode(render_mode, "make")
        self.render_width = _render_width(render_width, "make")
        self.timeout = _timeout(timeout, "make")
        teacher_text, teacher_file, teaching = _teacher_source(teacher)
        self._env = _roger.Environment(_native(curriculum), _native(stage), _native(context), _native(scenario or ""),
                                       _text_dict(params, "params"), _text_dict(skills, "skills"), mode == "tick",
                                       _tasks_source(tasks), teacher_text, _native(teacher_file), embedded, teaching)
        self._task_dims = self._env.task_dims
        self.task_space = _task_space(self._task_dims)  # a Dict space, or None: the stage has no tasks
        self._teaching = teaching and self._env.teaches
        if self._teaching:
            self._env.make_teacher(0)  # a teacher this environment cannot run is refused here, not at reset
        self._teacher = None  # made at the first reset that asks it for a task after a seed
        self._teacher_seed = None
        self._told = []  # the outcomes told to the teacher, in order (None: a task skipped, never told): what a copy tells its own
        self._asked = False  # the running episode's task is the teacher's, its outcome not yet told
        self._set_task = None  # set_task's task: (as the space holds it, as parameters)
        self._task = (None, [])  # the running episode's task
        self._stage_info = self._env.info
        self.actions = tuple(self._stage_info["actions"])
        _check_policy_actions(played, self.actions, "make")
        self.mode = mode
        fps = round(1.0 / self._stage_info["tick_seconds"]) if mode == "tick" else _DECISION_FPS
        self.metadata = {"render_modes": _RENDER_MODES, "render_fps": fps}
        self.action_space = spaces.Discrete(len(self.actions))
        n = len(self.actions)
        self.observation_space = _tick_space(n, self._stage_info) if mode == "tick" else _state_space(n)
        if mode == "tick":
            _check_tick_tasks(self._task_dims, self._stage_info)
            if self._teaching:
                _check_tick_teacher(self._env.teacher_body_change(), self._stage_info)
        self._stream = None  # [S, k]: the last explicit seed, and the unseeded resets since it
        self._running = False  # an episode waits for step()
        self._faulted = False  # the episode ended by an error (a copy's replay meets it again)

    def __repr__(self):
        i = self._stage_info
        return f"<roger.Env {i['curriculum']} stage {i['stage']} context {i['context']} ({self.mode})>"

    def _open(self, what):
        if self._env is None:
            hint = _closed_by_vector_hint(self._closed_by_vector) if self._closed_by_vector else ""
            raise RogerError(f"{what}: the environment is closed (make a new one){hint}")
        return self._env

    def _observe(self, state):
        state = state.astype(np.int64)
        if self.mode != "tick":
            return state
        obs = self._env.senses()
        obs["state"] = state
        return obs

    def _info(self, state, ended=False, time_out=False):
        e = self._env
        # The seed as numpy.uint64, as make_vec gives it: Gymnasium's vector environments gather it
        # in an array of its type, which holds every seed in [0, 2^64).
        info = {"sim_seconds": e.sim_seconds, "ticks": e.ticks, "decisions": e.decisions, "seed": np.uint64(e.seed),
                "state": {a: GAMMA_NAMES[g] for a, g in zip(self.actions, state)}}
        if self.task_space is not None or self._teaching:
            info["task"] = self.get_task()
            info["task_params"] = e.typed_params(self._task[1])  # as the scenario took them, numbers as numbers
        if ended:
            info["episode_reward"] = e.episode_reward
            info["success"] = info["is_success"] = e.success  # is_success: Stable-Baselines3's name
            info["time_out"] = time_out
        return info

    def _world(self, given):
        """The seed of this reset's world: `given`; else the next of the stream of the last
        explicit seed S, whose k-th unseeded reset plays mix(S, k) >> 1. An environment never
        seeded draws its S from the operating system, as Gymnasium's environments draw their
        generators, and plays the world of S first. The seeds it draws are below 2^63 (as when
        info["seed"] was gathered in int64 arrays; it is a numpy.uint64 now, and the worlds stay)."""
        if given is not None:
            self._stream = [given, 0]
            return given
        if self._stream is None:
            self._stream = [secrets.randbits(63), 0]
            return self._stream[0]
        self._stream[1] += 1
        return mix(*self._stream) >> 1

    def reset(self, *, seed=None, options=None):
        """Starts the episode in the world of `seed` (roger eval's --seed); without one, the next
        world of the environment's own stream (docs/python.md, Determinism and seeds). Seeds
        np_random as Gymnasium does. options={"task": {...}} generates the world with that task of
        task_space; without it, the task of set_task, else the teacher's, else the stage's own
        parameters. Returns (observation, info)."""
        with self._using("reset"):
            return self._reset(seed, options)

    def _reset(self, seed, options):
        env = self._open("reset")
        given = None if seed is None else _seed(seed, "reset")
        options = _options(options, "reset", ("task",))
        # {"task": None} is no task option, as set_task(None) is no task: the teacher's (or set_task's).
        given_task = options.get("task")
        task = None if given_task is None else env.task_of(given_task, "reset: options['task']")
        super().reset(seed=given)  # an unseeded reset leaves np_random running on
        self._tell()  # an episode left unfinished is the teacher's outcome as it stood
        seed = self._world(given)
        if given is not None:  # a seeded reset starts the teacher afresh too, as it starts the stream
            self._teacher, self._teacher_seed, self._told = None, None, []
        if task is None:
            task = self._set_task
        skipped = []
        while True:
            world = seed
            if task is None and self._teaching:
                # After 10 skips in one world the draws move to another, as roger train's do: one
                # layout may hold no task of a narrow space that others hold.
                layout = seed if len(skipped) < _SKIPS_PER_WORLD else mix(seed, len(skipped) // _SKIPS_PER_WORLD)
                world = self._teacher_task(env, layout, given)
            else:
                self._task = task or (None, [])
            self._running, self._faulted = False, True  # until the episode runs
            try:
                state, running = env.reset_task(world, self._task[1])
                break
            except PlacementError as e:
                if not self._asked:  # a task given by options or set_task is the caller's to fix
                    raise
                self._skip_task(e, skipped)
        self._running, self._faulted = running, False
        if not running:
            raise RogerError(f"reset: the episode of seed {world} ended before its first decision "
                             "(its absorbing function holds at once)")
        misfit = self._body_misfit()
        if misfit:
            self._refuse_body(world, misfit)
        info = self._info(state)
        if self._teaching:
            info["skipped_tasks"] = skipped
        return self._observe(state), info

    def _body_misfit(self):
        """In tick mode, how the episode's body differs from the one observation_space was made
        for (the stage's, read from its first held-out world), or None: a task or a teacher can
        set the body's parameters (LCAS lifts eye_pixels), and a Gymnasium space cannot change."""
        if self.mode != "tick":
            return None
        body, info = self._env.body, self._stage_info
        if body["eye_pixels"] != info["eye_pixels"]:
            return (f"eyes of {body['eye_pixels']} pixels, where observation_space's images have "
                    f"{info['eye_pixels']} (stage_info['eye_pixels'])")
        if body["joint_low"] != info["joint_low"] or body["joint_high"] != info["joint_high"]:
            return (f"joints read within {body['joint_low']} .. {body['joint_high']}, where observation_space's "
                    f"are within {info['joint_low']} .. {info['joint_high']}")
        return None

    def _refuse_body(self, world, misfit):
        """Refuses the episode just begun, whose observations would fall outside observation_space:
        a teacher's task is asked and never told, as a skipped one (a copy's teacher asks it too)."""
        self._running = False
        source = "the teacher's task" if self._asked else "the task"
        if self._asked:
            self._asked = False
            self._told.append(None)
        params = self._env.typed_params(self._task[1])
        raise RogerError(
            f"reset: tick mode's observation_space is made for the stage's body, but the world of seed {world} "
            f"({source} {params}) has another, with {misfit}: its observations would not be members of "
            "observation_space. Keep the body's parameters out of the tasks (make(..., teacher=False), or a "
            "teacher that does not set them), or use mode='decision'")

    def _teacher_task(self, env, seed, given):
        """Asks the teacher for this reset's task (made at the first reset that asks after a seed);
        returns the world seed to play: `seed`, or the level PLR replays unless the reset named one."""
        if self._teacher is None:
            self._teacher_seed = mix(seed, _TEACH)
            self._teacher = env.make_teacher(self._teacher_seed)
        point, params, level = self._teacher.next()
        self._task, self._asked = (point, params), True
        return level if level is not None and given is None else seed

    def _skip_task(self, error, skipped):
        """The teacher's task could not be placed (PlacementError): it is skipped, as roger train
        skips it (never played, never told), and shown in reset's info["skipped_tasks"]; a copy's
        teacher asks it too (None in the told list). 100 in a row: the space asks for worlds the
        scenario cannot build, and the reset says so."""
        self._asked = False
        self._told.append(None)
        skipped.append({"task": self.get_task(), "task_params": self._env.typed_params(self._task[1]),
                        "error": str(error)})
        if len(skipped) >= _MAX_SKIPPED_IN_A_ROW:
            raise RogerError(f"reset: the teacher's last {_MAX_SKIPPED_IN_A_ROW} tasks could not be placed in "
                             f"{_MAX_SKIPPED_IN_A_ROW // _SKIPS_PER_WORLD} world seeds: the task space asks for worlds "
                             f"the scenario cannot build. The last: {error}") from error

    def step(self, action):
        """Runs one decision: `action` until the next decision point (the state changes, or the
        action gives up). Returns (observation, reward, terminated, truncated, info): terminated
        when the absorbing state is reached or the stage's time-out passes (info["time_out"]
        tells which), truncated never (it is for limits a wrapper adds); with
        timeout="truncate", the time-out is truncated instead of terminated."""
        with self._using("step"):
            return self._step(action)

    def _step(self, action):
        env = self._open("step")
        a = _action(action, len(self.actions), f"step ({self._stage_info['stage']}/{self._stage_info['context']})")
        if env.running and not self._running:  # the episode the last reset refused (_refuse_body)
            raise RogerError("step: no episode is running: the last reset was refused (call reset first)")
        try:
            state, reward, terminated, time_out = env.step(a)
        except RogerError:
            self._faulted = self._faulted or self._running  # the episode ran, and the error ended it
            self._running = False
            raise
        self._running = not terminated
        if terminated:
            self._tell()
        truncated = time_out and self.timeout == "truncate"
        info = self._info(state, terminated, time_out)
        return self._observe(state), reward, terminated and not truncated, truncated, info

    def _tell(self):
        """Tells the teacher the outcome of the episode of its last task, once."""
        if not self._asked:
            return
        self._asked = False
        e = self._env
        outcome = (e.seed, e.success, e.episode_reward, e.sim_seconds)
        self._teacher.record(*outcome)
        self._told.append(outcome)

    def set_task(self, task):
        """Every later reset without options["task"] plays this task of task_space (RLlib's
        TaskSettableEnv); None gives the resets back to the teacher (or the stage's parameters)."""
        env = self._open("set_task")
        self._set_task = None if task is None else env.task_of(task, "set_task")

    def get_task(self):
        """The running (or last) episode's task as task_space holds it (a choice by its index);
        None when its world had the stage's own parameters."""
        self._open("get_task")
        # A real axis's value as Box.sample gives it (a 0-d float64 array), so that it is a member.
        return None if self._task[0] is None else {
            k: np.asarray(v, np.float64) if isinstance(v, float) else v for k, v in self._task[0].items()}

    def sample_tasks(self, n):
        """n tasks drawn from task_space with its own generator (RLlib's TaskSettableEnv): seed it,
        env.task_space.seed(S), for the same tasks every run."""
        self._open("sample_tasks")
        if self.task_space is None:
            raise RogerError("sample_tasks: the stage has no task space (give make(..., tasks={...}))")
        if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 0:
            raise RogerError(f"sample_tasks: a count of tasks is a non-negative integer, got {n!r}")
        return [self.task_space.sample() for _ in range(n)]

    def task_params(self, task):
        """A task of task_space as the scenario parameters it sets ({"shape": "spade", "obstacles": 3,
        ...}: numbers as numbers)."""
        env = self._open("task_params")
        return env.typed_params(env.task_of(task, "task_params")[1])

    @property
    def teacher_state(self):
        """The teacher's own state (its kind, step, level, mixture, levels...), as `roger train`'s
        checkpoints record it; None before its first task."""
        import json
        self._open("teacher_state")
        return None if self._teacher is None else json.loads(self._teacher.state())

    def render(self):
        """With render_mode "rgb_array": the world now as `roger render --width render_width`
        draws it, an H x W x 3 uint8 array; else None."""
        with self._using("render"):
            env = self._open("render")
            if self.render_mode is None:
                _warn_no_render_mode("make")
                return None
            if not env.begun:
                raise RogerError("render: no world yet (call reset first)")
            return env.render(self.render_width)

    def close(self):
        """Frees the world and the Lua state; every later call of a method but close (and of
        teacher_state) raises RogerError. What describes the environment (actions, stage_info,
        the spaces, metadata, spec) stays readable, and a copy of it is closed too. Called from
        another thread while a reset or step runs, it waits for that call to end."""
        self._closing = True  # a call of another thread that finds the lock held by close waits for it
        with self.__dict__.get("_lock") or contextlib.nullcontext():
            self._teacher = None  # first: a Lua teacher lives in the environment's Lua state
            if getattr(self, "_env", None) is not None:
                self._closed_by_vector = _called_from_a_vector_env()
            self._env = None

    def _closed_now(self):
        return self._env is None

    def _state(self):
        episode = (self._env.seed, self._env.actions_taken, self._faulted) if self._env.begun else None
        return {"stream": self._stream, "episode": episode, "task": self._task, "set_task": self._set_task,
                "teacher": (self._teacher_seed, list(self._told), self._asked)}

    def _restore(self, state):
        self._stream = state["stream"]
        self._task, self._set_task = state["task"], state["set_task"]
        self._restore_teacher(*state["teacher"])
        if state["episode"] is None:
            return
        seed, actions, faulted = state["episode"]
        self._faulted = faulted
        try:
            self._env.replay(seed, actions, self._task[1])
            self._running = self._env.running and self._body_misfit() is None  # refused as in the original
        except RogerError as e:
            if not faulted:  # the original's episode ran on: the replay should have too
                raise RogerError(f"copy: the episode of seed {seed} did not replay ({len(actions)} actions): {e}") from e

    def _restore_teacher(self, seed, told, asked):
        """A copy's teacher: made with the original's seed and told the same outcomes, it asks the
        same tasks (a teacher is a function of its seed and what it was told)."""
        self._teacher_seed, self._told, self._asked = seed, [], False
        if seed is None:
            return
        self._teacher = self._env.make_teacher(seed)
        for outcome in told:
            self._teacher.next()
            if outcome is None:  # a task the scenario could not place: asked, skipped, never told
                self._told.append(None)
                continue
            self._teacher.record(*outcome)
            self._told.append(tuple(outcome))
        if asked:
            point, _, _ = self._teacher.next()
            if point != self._task[0]:
                raise RogerError(f"copy: the teacher asked {point} where the original's episode has {self._task[0]}")
            self._asked = True


def _check_tick_tasks(dims, info):
    """Refuses, at make, a task space whose tasks set the eyes' pixels in tick mode: the images'
    shape is observation_space's, fixed at make (the teacher's settings beside the space are
    checked at each reset)."""
    for d in dims:
        if d["name"] == "eye_pixels":
            raise RogerError(
                f"make: mode='tick' observes images of the stage's eyes (2 x {info['eye_pixels']} pixels, "
                f"stage_info['eye_pixels']) in a space fixed at make, but the task space varies eye_pixels "
                f"({d['text']}): its worlds' images would not fit observation_space. Fix eye_pixels with params, "
                "leave it out of tasks, or use mode='decision'")


def _check_tick_teacher(change, info):
    """Refuses, at make, a stage whose teacher sets a body parameter beside the task space (an
    LCAS teacher lifting eye_pixels) in tick mode: every reset of such a world would be refused."""
    if change is None:
        return
    levels = ", ".join(change["levels"])
    raise RogerError(
        f"make: mode='tick' observes the stage's body (eyes of {info['eye_pixels']} pixels, "
        f"stage_info['eye_pixels']) in a space fixed at make, but its teacher, {change['teacher']}, lifts "
        f"{change['lift']} through {levels}: at {change['lift']} = {change['level']} its worlds have "
        f"{change['misfit']}, and their observations would not fit observation_space. Give make(..., teacher=False) "
        f"(the stage's own body; params={{'{change['lift']}': ...}} with it fixes another), or use mode='decision'")


def _tick_space(n, info):
    """The tick mode's observations: the state and the raw senses, float32 and bounded where the
    stage's body bounds them (images of its eyes' pixels, joints within its ranges)."""
    pixels, inf = info["eye_pixels"], np.inf
    touch_low = np.tile(np.array([0, 0, 0, -1, -1], np.float32), (3, 1))    # contact, force, friction, normal x, y
    touch_high = np.tile(np.array([1, inf, inf, 1, 1], np.float32), (3, 1))
    return spaces.Dict({
        "state": _state_space(n),
        "images": spaces.Box(0, 255, (2, pixels, 3), np.uint8),
        "stimulus": spaces.Box(0.0, 1.0, (2, pixels), np.float32),
        "touch": spaces.Box(touch_low, touch_high, (3, 5), np.float32),
        "joints": spaces.Box(np.array(info["joint_low"], np.float32), np.array(info["joint_high"], np.float32),
                             (8,), np.float32),
        "joint_velocities": spaces.Box(-inf, inf, (8,), np.float32),
    })


def _reset_seeds(seed, n):
    """reset's seed as the extension takes it: which environments are given one, and which."""
    seeded, seeds = np.zeros(n, np.uint8), np.zeros(n, np.uint64)
    if seed is None:
        return seeded, seeds
    if isinstance(seed, np.ndarray) and seed.ndim != 1:  # a 0-d array has no len(); as Env.reset refuses it
        raise RogerError(f"reset: a seed is an integer in [0, 2^64), or a list of one per environment ({n}), "
                         f"got {_short(seed)}")
    if isinstance(seed, (list, tuple, np.ndarray)):
        if len(seed) != n:
            raise RogerError(f"reset: a list of seeds has one per environment ({n}), got {len(seed)}")
        for i, s in enumerate(seed):
            if s is not None:
                seeded[i], seeds[i] = 1, _seed(s, f"reset (seed of environment {i})")
        return seeded, seeds
    first = _seed(seed, "reset")
    for i in range(n):
        seeded[i], seeds[i] = 1, (first + i) % 2**64
    return seeded, seeds


_APART_TRIES = 100000
_SEEDS = 2**64  # the seeds of worlds: schedules wrap past 2^64 - 1 to 0
_HALF = 2**63


def _meet(a, b, n):
    """Whether the schedules a, a + n, a + 2n, ... and b, b + n, ... (modulo 2^64) meet soon: the
    distance between a and b the shorter way round the 2^64 seeds is a multiple of n, so that one
    reaches the other's worlds after that distance / n episodes. Schedules that do not meet play
    distinct worlds for at least 2^63 / n episodes each (a shared world would need a distance of
    at least 2^64 - 2^63 covered in steps of n). For seeds less than 2^63 apart this is the same
    residue modulo n; found by a probe: residues alone ignored the wrap past 2^64 - 1, which
    changes the residue when n does not divide 2^64, so that 3 environments seeded [2^64 - 1,
    None, None] played 2^64 - 1, 2, 5, ..., the worlds environment 2 had just played."""
    d = (b - a) % _SEEDS
    return min(d, _SEEDS - d) % n == 0


class _Worlds:
    """A set of next worlds of schedules, asked whether a schedule meets any of them (_meet) without
    going through them all: of a world w, the shift of the others by a multiple of 2^64 that lies
    within 2^63 of it is what the residue modulo n is taken of (a reset of 4096 environments asks
    it thousands of times)."""

    def __init__(self, n):
        self.n = n
        self.near = {}  # residue of w: sorted worlds w
        self.below = {}  # residue of w - 2^64: sorted worlds (those more than 2^63 above the asker)
        self.above = {}  # residue of w + 2^64: sorted worlds (those more than 2^63 below the asker)
        self.tried = {}  # _own_schedule's: of a seed, the last k tried

    def add(self, w):
        for table, shifted in ((self.near, w), (self.below, w - _SEEDS), (self.above, w + _SEEDS)):
            bisect.insort(table.setdefault(shifted % self.n, []), w)

    def meets(self, a):
        r = a % self.n
        near = self.near.get(r, ())
        k = bisect.bisect_left(near, max(0, a - _HALF))
        if k < len(near) and near[k] <= a + _HALF:
            return True
        below, above = self.below.get(r), self.above.get(r)
        return bool(below and below[-1] > a + _HALF) or bool(above and above[0] < a - _HALF)


def _ahead_order(indices, nexts, given):
    """`indices` in the order of their next worlds, the one ahead first: the one the others would
    reach going up. Of equal ones, one given that seed goes first (found by a probe: an environment
    left out mid-episode, of a lower index, went on to the world another was given, so that both
    played it), then the first in index order. The seeds are a circle (they wrap past 2^64 - 1 to
    0), cut at the widest gap between the worlds: where that is the one across 2^64 (always so for
    worlds less than 2^63 apart, such as any below 2^63) the order is that of the seeds, as it has
    always been. By the seeds alone 2^64 - 1 would go ahead of 5 (a masked reset's [2^64 - 1, 4,
    5], found by a probe), where 2^64 - 1 reaches 5 in 2 episodes and 5 reaches it in 6 * 10^18."""
    points = sorted({nexts[i] for i in indices})
    origin, widest = 0, _SEEDS - (points[-1] - points[0])
    for low, high in zip(points, points[1:]):
        if high - low > widest:
            origin, widest = high, high - low
    return sorted(indices, key=lambda i: (-((nexts[i] - origin) % _SEEDS), i not in given, i))


def _apart_from_seeded(vec, mask, seeded, seeds):
    """Keeps a reset's schedules apart where seeds given would make them meet (_meet: one would
    replay the other's worlds, at once or at a later autoreset). Of the environments given seeds,
    and those the mask leaves out mid-episode (by the world they would play next), the one ahead
    of those that meet (the highest seed, the first of equal ones) goes on along its schedule;
    each other given a seed plays it first, then continues on a schedule of its own
    (_own_schedule), and each other left out continues on one from the world it would have played
    next. The returned {environment: the world it continues at} is for VecEnvironment.continue_at
    after the reset. An environment reset without a seed goes on along its schedule unless that
    meets a seed given: it then begins a schedule of its own at once, in `seeds`. Resets fully
    unseeded, and an int seed S on every environment (S + i: the distances are below num_envs,
    wrapped or not), never meet this (docs/python.md, Batches)."""
    n = len(mask)
    given = [i for i in range(n) if mask[i] and seeded[i]]
    if not given:
        return {}
    running = [i for i, begun in enumerate(vec.begun) if begun and not mask[i]]
    nexts = []
    for i, (base, started, *_) in enumerate(vec.snapshot()):
        nexts.append(int(seeds[i]) if mask[i] and seeded[i] else (int(base) + int(started) * n) % _SEEDS)
    later = _apart_given(given, running, nexts, n)
    by_seeded = _Worlds(n)
    for j in given:
        by_seeded.add(nexts[j])
    moved_on = {j for j in later if j not in given}  # left out, their next world no longer theirs
    taken = _Worlds(n)
    for w in [nexts[j] for j in range(n) if j not in moved_on] + list(later.values()):
        taken.add(w)
    for i in range(n):
        if not mask[i] or seeded[i] or not by_seeded.meets(nexts[i]):
            continue
        world = _own_schedule(nexts[i], taken)
        seeded[i], seeds[i], nexts[i] = 1, world, world
    return later


def _apart_given(given, running, nexts, n):
    """Of the environments given seeds and those running on (left out of the reset), those whose
    schedules would meet another's (all but the one ahead, _ahead_order, of each that meet), each
    with the world it continues at: one given a seed after its first, one running on instead of
    the world it would have played next."""
    seen, movers = _Worlds(n), []
    for i in _ahead_order(given + running, nexts, set(given)):
        if seen.meets(nexts[i]):
            movers.append(i)
        seen.add(nexts[i])
    movers.sort()
    moving, given = set(movers), set(given)
    ahead = _Worlds(n)  # the next worlds that stay, and a mover's first world (its seed given)
    for j in range(len(nexts)):
        if j not in moving or j in given:
            ahead.add(nexts[j])
    later = {}
    for i in movers:
        # One given a seed goes on from the seed it would have played second, as an unseeded
        # entry's from the one it would play; one running on, from the world it would play next.
        start = (nexts[i] + n) % _SEEDS if i in given else nexts[i]
        later[i] = _own_schedule(start, ahead)
    return later


def _own_schedule(seed, taken):
    """A schedule of its own for an environment whose schedule would meet another's: mix(seed, k) >> 1
    for k = 1, 2, ... the first that meets none of `taken` (a _Worlds), which it joins. Of several
    from one seed (a list of equal seeds), each goes on from the k after the last one's: the worlds
    before are still taken (`taken` only grows), so the world is the same, found without trying
    them all again (4096 equal seeds tried 16 million)."""
    k = taken.tried.get(seed, 0)
    while k < _APART_TRIES - 1:
        k += 1
        world = mix(seed, k) >> 1
        if not taken.meets(world):
            break
    taken.tried[seed] = k
    taken.add(world)
    return world


def _refuse_out_of_range(actions, k):
    """Refuses an action outside [0, k) by its value as given: the extension's int64 would read a
    uint64 past 2^63 - 1 as a negative number."""
    bad = np.flatnonzero((actions < 0) | (actions >= k))
    if bad.size:
        i = int(bad[0])
        raise RogerError(f"step: action {int(actions[i])} of environment {i} is not in [0, {k})")


def _reset_mask(options, n):
    mask = options.pop("reset_mask", None)
    if mask is None:
        return np.ones(n, np.uint8)
    if not isinstance(mask, np.ndarray) or mask.dtype != np.bool_ or mask.shape != (n,) or not mask.any():
        raise RogerError(f"reset: options['reset_mask'] must be a numpy bool array of shape ({n},) with at least "
                         f"one True, got {mask!r}")
    return mask.astype(np.uint8)


# make_vec's counts, each at most (bound, why): checked before the extension, whose int would take
# neither a larger one (docs/python.md, Batches).
_COUNT_BOUNDS = {
    "num_envs": (4096, "each environment holds its own Lua state and world"),
    "threads": (1024, "more than num_envs run as num_envs"),
    "max_episode_steps": (2**31 - 1, "2^31 - 1: the engine counts an episode's decisions in 32 bits"),
}


def _masked(info, key, values, mask):
    """Puts key and its mask _key in a batch's info, as Gymnasium's VectorEnv._add_info: only when
    some environment has it (an info of a step where no episode ended has no final_info)."""
    if mask.any():
        info[key], info["_" + key] = values, mask


class VecEnv(_Copyable, _VecBase):
    """num_envs environments of one stage, stepped together on C++ threads with the GIL released:
    a gymnasium.vector.VectorEnv when gymnasium is importable (docs/python.md, "Batches").

    Environment i's episodes run in the worlds of seeds b_i, b_i + num_envs, b_i + 2 num_envs, ...
    (reset(seed=S) makes b_i = S + i; an unseeded reset goes on along the schedule). An ended
    episode's successor begins as metadata["autoreset_mode"] says: at the environment's next step
    (NEXT_STEP, the default), at once (SAME_STEP, the last observation in info["final_obs"]), or
    when the caller resets it (DISABLED). Results depend on the seeds and actions only, never on
    the thread count. With timeout="truncate" a time-out is reported as truncated."""

    _SHARED = ("the batch is being used by another thread at the same time: one make_vec batch is not shared "
               "between threads (its worlds already step on its own threads); call it from one thread, or make "
               "one batch per thread")

    def __init__(self, curriculum, stage, context, num_envs, threads=None, params=None, skills=None, scenario=None,
                 autoreset_mode=AutoresetMode.NEXT_STEP, render_mode=None, render_width=1000, timeout="terminate",
                 mode="decision", policy=None, teacher=None, max_episode_steps=None):
        # Held by reset, step, render and copies; close waits for it. The batch's C++ environments
        # are stepped by its worker threads with the GIL released: two calls at once would step the
        # same worlds from two threads and corrupt them (an abort, or a hang), so one is refused.
        self._lock = threading.RLock()
        self._maker = os.getpid()  # the process whose threads step the batch (_open)
        if isinstance(policy, Policy):
            policy = policy.path
        curriculum, scenario, teacher, policy = map(_path_text, (curriculum, scenario, teacher, policy))
        skills = _skill_paths(skills)
        self._init = {"curriculum": curriculum, "stage": stage, "context": context, "num_envs": num_envs,
                      "threads": threads, "params": params, "skills": skills, "scenario": scenario,
                      "autoreset_mode": autoreset_mode, "render_mode": render_mode, "render_width": render_width,
                      "timeout": timeout, "mode": mode, "policy": policy}
        if teacher is not None:  # recorded only when given: a copy's recipe of an older pickle has none
            self._init["teacher"] = teacher
        if max_episode_steps is not None:  # as teacher
            self._init["max_episode_steps"] = max_episode_steps
        self._recipe = _recipe(self._init)
        if teacher not in (None, False):
            raise RogerError(f"make_vec: teacher is None (the stage's, refused when it has one) or False (none), "
                             f"got {teacher!r}: the threaded batch runs no teacher; vectorize roger.make "
                             "environments for one (gymnasium.make_vec(..., vectorization_mode='sync'))")
        if mode != "decision":  # the ids' keyword, which gymnasium.make_vec hands over
            raise RogerError(f"make_vec: the threaded batch steps decisions (mode='decision'), got mode={mode!r}; "
                             "for tick mode vectorize single environments (gymnasium.make_vec(..., "
                             "vectorization_mode='sync'))")
        _names(curriculum, stage, context, "make_vec")
        for name, value in (("num_envs", num_envs), ("threads", threads), ("max_episode_steps", max_episode_steps)):
            if not _positive_integer(value) and (name == "num_envs" or value is not None):  # None: the default
                raise RogerError(f"make_vec: {name} must be a positive integer, got {_short(value)}")
            # Found by a probe: 2**40 reached the extension's int and raised pybind11's TypeError with
            # its signature, and num_envs=2**31 - 1 was taken and allocated until std::bad_alloc.
            bound, why = _COUNT_BOUNDS[name]
            if value is not None and value > bound:
                raise RogerError(f"make_vec: {name} is at most {bound} ({why}), got {_short(value)}")
        self.timeout = _timeout(timeout, "make_vec")
        try:
            mode = AutoresetMode(autoreset_mode)
        except ValueError:
            raise RogerError(f"make_vec: autoreset_mode must be one of {[m.value for m in AutoresetMode]}, "
                             f"got {autoreset_mode!r}") from None
        self.render_mode = _render_mode(render_mode, "make_vec")
        self.render_width = _render_width(render_width, "make_vec")
        if threads is None:
            threads = min(int(num_envs), len(os.sched_getaffinity(0)), _COUNT_BOUNDS["threads"][0])
        params, embedded, played = _with_policy(policy, curriculum, stage, context, params, scenario, "make_vec")
        self._vec = _roger.VecEnvironment(_native(curriculum), _native(stage), _native(context), _native(scenario or ""),
                                          _text_dict(params, "params"), _text_dict(skills, "skills"),
                                          int(num_envs), int(threads), mode.value, embedded)
        self._vec.decision_cap = int(max_episode_steps or 0)
        # A teacher's worlds would not be roger train's tasks: refused, not ignored (teacher=False asks for none).
        if self._vec.teaches and teacher is not False:
            self._vec = None
            raise RogerError(f"make_vec: stage '{stage}' chooses each episode's task with a teacher, which the "
                             "threaded batch does not run; give make_vec(..., teacher=False) for the stage's own "
                             "parameters in every world, or vectorize roger.make environments "
                             "(gymnasium.make_vec(..., vectorization_mode='sync')), each with its teacher")
        self.metadata = {"autoreset_mode": mode, "render_modes": _RENDER_MODES, "render_fps": _DECISION_FPS}
        self.autoreset_mode = mode
        # For each environment no reset has begun yet, the base seed a seeded reset that left it out
        # (its reset_mask entry False) gave it: its first reset starts there, so that it does not
        # replay the worlds of the others' schedules (None: the batch's S = 0, environment i at i).
        self._pending = [None] * int(num_envs)
        # Each environment no reset has begun because the last reset that asked for it failed: that
        # reset's error (step refuses it saying so, where "not reset yet" would be false).
        self._reset_failed = {}
        self._stage_info = self._vec.info
        self.actions = tuple(self._stage_info["actions"])
        try:
            _check_policy_actions(played, self.actions, "make_vec")
        except RogerError:
            self._vec = None
            raise
        self.num_envs = int(num_envs)
        self.threads = self._vec.threads
        self.single_action_space = spaces.Discrete(len(self.actions))
        self.single_observation_space = _state_space(len(self.actions))
        if _batch_space is not None:
            self.action_space = _batch_space(self.single_action_space, self.num_envs)
            self.observation_space = _batch_space(self.single_observation_space, self.num_envs)
        else:
            # As gymnasium.vector.utils.batch_space batches them: Discrete into MultiDiscrete,
            # MultiDiscrete into a Box of its bounds.
            self.action_space = spaces.MultiDiscrete(np.full(self.num_envs, len(self.actions), dtype=np.int64))
            self.observation_space = spaces.Box(np.zeros((self.num_envs, len(self.actions)), np.int64),
                                                np.full((self.num_envs, len(self.actions)), 2, np.int64),
                                                dtype=np.int64)

    def __repr__(self):
        i = self._stage_info
        return f"<roger.VecEnv {i['curriculum']} stage {i['stage']} context {i['context']} x{self.num_envs}>"

    def _open(self, what):
        if self._vec is None:
            raise RogerError(f"{what}: the vector environment is closed (make a new one)")
        if self._maker != os.getpid() and self.threads > 1:
            # Found by a probe: a batch used in a fork()ed child (multiprocessing's fork start
            # method, os.fork) hung forever: its worker threads exist only in the process that
            # made it, and the step waited for them. One thread steps in the caller's own.
            raise RogerError(
                f"{what}: this make_vec batch was made in process {self._maker} and is used in process "
                f"{os.getpid()} (a fork()ed child): its {self.threads} threads are the other process's and "
                "do not run here; make a new batch in this process (roger.make_vec(...), or copy.deepcopy(batch), "
                "which continues its worlds), or make the batch with threads=1")
        return self._vec

    def reset(self, *, seed=None, options=None):
        """Resets every environment (those of options["reset_mask"] alone, when given): seed None
        (each goes on along its schedule), an int S (environment i in world S + i) or a list of
        one int or None per environment (each plays its seed first; schedules that would meet
        continue apart: docs/python.md, Batches). Returns (observations [num_envs, |Psi|], info)."""
        with self._using("reset"):
            return self._reset(seed, options)

    def _reset(self, seed, options):
        vec = self._open("reset")
        options = _options(options, "reset", ("reset_mask",))
        mask = _reset_mask(options, self.num_envs)
        seeded, seeds = _reset_seeds(seed, self.num_envs)
        super().reset(seed=_seed(seed, "reset") if isinstance(seed, (numbers.Integral, np.integer)) else None)
        pending = list(self._pending)
        for i, begun in enumerate(vec.begun):
            if begun:
                continue
            if not mask[i]:  # left out again: a seed given now is where it will start
                if seeded[i]:
                    pending[i] = int(seeds[i])
            elif not seeded[i] and pending[i] is not None:
                seeded[i], seeds[i] = 1, pending[i]
        later = _apart_from_seeded(vec, mask, seeded, seeds)
        try:
            r = vec.reset(mask, seeded, seeds)
        except RogerError as e:
            # Found by a probe: after a reset that raised (a scenario's generate erring in one
            # environment's world), step said that environment "has not been reset yet (its
            # reset_mask entry was False at every reset)".
            begun, cause = vec.begun, str(e).splitlines()[0] if str(e) else type(e).__name__
            for i in map(int, np.flatnonzero(mask)):
                if begun[i]:
                    self._reset_failed.pop(i, None)
                else:
                    self._reset_failed[i] = cause if len(cause) <= 300 else cause[:300] + "..."
            raise
        finally:  # also after a failed reset: the schedules are what its next step begins along
            for i, world in later.items():
                vec.continue_at(i, world)
        for i in np.flatnonzero(mask):
            self._reset_failed.pop(int(i), None)
        self._pending = [None if vec.begun[i] else p for i, p in enumerate(pending)]
        info, m = {}, mask.astype(bool)
        for key in ("seed", "sim_seconds", "ticks", "decisions"):
            _masked(info, key, r[key], m)
        return r["states"].astype(np.int64), info

    def step(self, actions):
        """Steps every environment with its action (an environment that begins its next episode
        in this step ignores its action). Returns numpy arrays (observations, rewards, terminated,
        truncated) and info as Gymnasium 1.x's vector environments give it. A Lua fault in one
        environment raises ScriptError naming it (.env, .failed), with every environment's
        outcome of the step as .results; the faulted episodes are over (truncated)."""
        with self._using("step"):
            return self._step(actions)

    def _step(self, actions):
        vec = self._open("step")
        a = np.asarray(actions)
        # A list mixing bools with indices reads as integers (found by a probe: [True, 0, 1, 0] was taken).
        if _holds_bool(actions):
            raise RogerError(f"step: expected {self.num_envs} integer actions, got a list holding a bool: "
                             f"{list(actions)!r} (an action is an index, 0 to {len(self.actions) - 1})")
        if a.shape != (self.num_envs,) or not np.issubdtype(a.dtype, np.integer):
            raise RogerError(f"step: expected {self.num_envs} integer actions, got {a.dtype} array of shape {a.shape}")
        _refuse_out_of_range(a, len(self.actions))
        if self._reset_failed:
            i, cause = min(self._reset_failed.items())
            raise RogerError(f"step: environment {i} of {self.num_envs} has no episode: the last reset that asked for "
                             f"it failed ({cause}); reset it again (reset(), or reset(options={{'reset_mask': ...}}) "
                             "for it alone)")
        try:
            r = vec.step(a.astype(np.int64))
        except RogerError as e:
            if hasattr(e, "results"):
                e.results = self._outcome(e.results)
            raise
        return self._outcome(r)

    def _outcome(self, r):
        everyone = np.ones(self.num_envs, bool)
        info = {}
        for key in ("seed", "sim_seconds", "ticks", "decisions"):
            _masked(info, key, r[key], everyone)
        ended = r["ended"]
        last = {}
        for key in ("seed", "sim_seconds", "ticks", "decisions"):
            _masked(last, key, r["last_" + key], ended)
        for key in ("episode_reward", "success", "time_out"):
            _masked(last, key, r[key], ended)
        _masked(last, "is_success", r["success"], ended)  # Stable-Baselines3's name
        if self.autoreset_mode == AutoresetMode.SAME_STEP:
            final_obs = np.full(self.num_envs, None, dtype=object)
            for i in np.flatnonzero(ended):
                final_obs[i] = r["last_states"][i].astype(np.int64)
            _masked(info, "final_obs", final_obs, ended)
            _masked(info, "final_info", last, ended)
        elif ended.any():
            for key in ("episode_reward", "success", "is_success", "time_out"):
                _masked(info, key, last[key], ended)
        terminated, truncated = r["terminated"], r["failed"] | r["truncated"]
        if self.timeout == "truncate":
            truncated |= r["time_out"]
            terminated = terminated & ~r["time_out"]
        return r["states"].astype(np.int64), r["rewards"], terminated, truncated, info

    def render(self):
        """With render_mode "rgb_array": every environment's world now (a tuple of H x W x 3
        uint8 arrays, as Env.render); else None."""
        with self._using("render"):
            vec = self._open("render")
            if self.render_mode is None:
                _warn_no_render_mode("make_vec")
                return None
            return tuple(vec.render(i, self.render_width) for i in range(self.num_envs))

    def close_extras(self, **kwargs):
        """Frees the batch; called from another thread while a reset or step runs, it waits for
        that call to end (as Env.close)."""
        self._closing = True  # a call of another thread that finds the lock held by close waits for it
        with self.__dict__.get("_lock") or contextlib.nullcontext():
            self._vec = None

    def _closed_now(self):
        return self._vec is None

    def _state(self):
        return {"envs": self._vec.snapshot(), "pending": list(self._pending), "reset_failed": dict(self._reset_failed)}

    def _restore(self, state):
        self._vec.restore(state["envs"])
        self._pending = list(state["pending"])
        self._reset_failed = dict(state.get("reset_failed", {}))  # a pickle of an older version has none


class Policy:
    """A policy.json written by `roger train`: act(obs) is the action `roger eval` takes, in the
    environment policy.make() makes (its stage and context with the trial's own parameters and
    learned skills, as `roger eval --policy` plays it)."""

    def __init__(self, path):
        import json
        # Found by a probe: load_policy(None) said "None: cannot read the policy file".
        if not isinstance(path, (str, bytes, os.PathLike)):
            raise RogerError(f"load_policy: expected the path of a policy.json (a str or os.PathLike), "
                             f"got {type(path).__name__} {_short(path)}")
        self._p = _roger.Policy(_native(path))
        self.path = str(path)
        self.actions = tuple(self._p.actions)
        self.stage, self.context, self.seed = self._p.stage, self._p.context, self._p.seed
        # The curriculum the trial ran (as roger train recorded it: a path, or None for a file
        # that records none) and the learned skills embedded in the file, by name.
        self.curriculum = self._p.curriculum or None
        self.skills = tuple(sorted(json.loads(self._p.skills_json)))
        self._params = None

    @property
    def params(self):
        """The scenario parameters the trial trained with beyond its stage's and context's (`roger
        train --set`, or the level an LCAS teacher lifted), which `roger eval --policy` sets as the
        trial's own: the file's extra.params that differ from what the stage and context of the
        recorded curriculum give now, as text ({"robot_distance": "1.9", "shape": "spade"})."""
        if self._params is None:
            if self.curriculum is None:
                raise RogerError(f"params: {self.path} records no curriculum (extra.curriculum); "
                                 "make(curriculum, ...) with its params given")
            self._params = dict(self._p.trial_params(_native(self.curriculum), ""))
        return dict(self._params)

    def make(self, **kwargs):
        """The environment `roger eval --policy` plays this policy in: roger.make(curriculum, stage,
        context, policy=self, teacher=False, **kwargs), the curriculum the file records unless
        kwargs give one. Any other keyword of make may be given: params over the trial's own,
        skills over those the file embeds, teacher (roger eval runs none, hence False)."""
        given = kwargs.pop("curriculum", None)
        curriculum = given or self.curriculum
        if curriculum is None:
            raise RogerError(f"make: {self.path} records no curriculum (extra.curriculum): give it, "
                             "policy.make(curriculum='curricula/paper.lua')")
        for key in ("stage", "context", "policy"):
            if key in kwargs:
                raise RogerError(f"make: the policy gives {key} ({getattr(self, key, self.path)!r}); "
                                 f"to play it elsewhere use roger.make(curriculum, stage, context, ...) without policy")
        kwargs.setdefault("teacher", False)
        try:
            return make(curriculum, self.stage, self.context, policy=self, **kwargs)
        except RogerError as e:
            # The recorded name is as roger train was given it, from the folder it ran in (found by a
            # probe: 'mycur.lua' from a notebook elsewhere said only that no such curriculum exists).
            if given or "no curriculum " not in str(e):
                raise
            raise RogerError(f"make: {self.path} records the curriculum {self.curriculum!r} as roger train was "
                             f"given it, from the folder it ran in, and it is not found from here: {e}; give it, "
                             f"policy.make(curriculum='path/to/{os.path.basename(self.curriculum)}')") from None

    def act(self, obs):
        """The greedy action (QTable::policy_action) of a controller-state vector: integers 0, 1,
        2 (floats only when whole numbers)."""
        _refuse_tick_observation(obs, "act", f"a vector of {len(self.actions)} controller states, the integers "
                                             "0 (NOREF), 1 (!CONV), 2 (CONV)")
        o = np.asarray(obs)
        if o.dtype.kind not in "iuf" or (o.dtype.kind == "f" and not np.array_equal(o, np.trunc(o))) or _holds_bool(obs):
            raise RogerError(f"act: an observation holds the integers 0 (NOREF), 1 (!CONV), 2 (CONV), "
                             f"got {_short(obs)}")
        return self._p.act(o.astype(np.int64))

    @property
    def q(self):
        """The Q table, one row per state (state_index(obs)), one column per action: a read-only
        copy (a write to it would change nothing the policy acts on, so it raises)."""
        q = self._p.q
        q.flags.writeable = False
        return q

    def __reduce__(self):
        # A copy (pickle, deepcopy) loads the same file again, by its absolute path: it may be made
        # in another working directory (a worker's), as an environment's copy reads its files.
        return Policy, (os.path.abspath(self.path),)

    def __repr__(self):
        return f"<roger.Policy {self.path}: stage {self.stage} context {self.context}, actions {self.actions}>"


def make(curriculum, stage, context, params=None, skills=None, scenario=None, mode="decision", render_mode=None,
         render_width=1000, timeout="terminate", tasks=None, teacher=None, policy=None):
    """An environment of `stage` in `context` of a curriculum (a path or a bare name: "paper").

    params: scenario parameters over the stage's ({"shape": "spade"}, as --set); skills: each
    learned skill the context uses, {"Phi_SG": "out/sg/policy.json"} (as --skill; a path or a
    Policy); scenario:
    another scenario than the stage's; mode: "decision" (semi-MDP) or "tick" (every control tick,
    raw senses in a Dict observation); render_mode: None or "rgb_array" (render() draws what
    `roger render --width render_width` draws); timeout: "terminate" (the stage's time-out ends
    the episode, as for the engine's learner) or "truncate" (reported as a truncation). With
    gymnasium importable, env.spec is that of roger/Stage-v0 with these arguments, so spec.make()
    builds the same environment. tasks: another task space than the stage's, {"obstacles":
    roger.axis.int(0, 6), ...} (env.task_space is its Gymnasium Dict space); teacher: another
    teacher than the stage's, Lua text ("roger.teacher.alp_gmm{fit_every = 20}", "function(history,
    rng) ... end") or a .lua file that returns one, or False for none (docs/python.md, Tasks and
    teachers); policy: a policy.json of this stage and context (a path or a Policy) whose trial's own
    parameters are set under params and whose embedded learned skills bind those skills does not
    give, as `roger eval --policy` plays it (Policy.make makes it so)."""
    if isinstance(policy, Policy):
        policy = policy.path
    curriculum, scenario, teacher, policy = map(_path_text, (curriculum, scenario, teacher, policy))
    kwargs = {"curriculum": curriculum, "stage": stage, "context": context, "params": params,
              "skills": _skill_paths(skills), "scenario": scenario, "mode": mode, "render_mode": render_mode,
              "render_width": render_width, "timeout": timeout, "tasks": tasks, "teacher": teacher, "policy": policy}
    env = Env(**kwargs)
    if _gym is not None:
        env.spec = _gym.envs.registration.EnvSpec("roger/Stage-v0", entry_point="roger:Env",
                                                  vector_entry_point="roger:make_vec",
                                                  kwargs={**kwargs, "tasks": _tasks_text(tasks)})
    return env


def make_vec(curriculum, stage, context, num_envs, threads=None, params=None, skills=None, scenario=None,
             autoreset_mode=AutoresetMode.NEXT_STEP, render_mode=None, render_width=1000, timeout="terminate",
             mode="decision", policy=None, teacher=None, max_episode_steps=None):
    """num_envs environments (a positive integer, at most 4096) stepped together in C++ threads
    (VecEnv), in the process that made them (a fork()ed child makes its own); threads (a positive
    integer, at most 1024) defaults to min(num_envs, the cores this process may use);
    autoreset_mode an AutoresetMode (or its value, "NextStep", "SameStep", "Disabled"); timeout as
    make's. The vector entry point of the registered ids (gymnasium.make_vec(id, num_envs,
    vectorization_mode="vector_entry_point")), which hands over make's keywords: mode must then be
    "decision"; policy as make's; teacher None (a stage with a teacher is refused: the batch runs
    none) or False (none: every world has the stage's own parameters, as make(...,
    teacher=False)); max_episode_steps (a positive integer up to 2^31 - 1, or None for none) cuts
    an episode still running after that many decisions short, as Gymnasium's TimeLimit does
    (reported as truncated; gymnasium.make_vec hands it over)."""
    return VecEnv(curriculum, stage, context, num_envs, threads=threads, params=params, skills=skills,
                  scenario=scenario, autoreset_mode=autoreset_mode, render_mode=render_mode,
                  render_width=render_width, timeout=timeout, mode=mode, policy=policy, teacher=teacher,
                  max_episode_steps=max_episode_steps)


def _with_policy(policy, curriculum, stage, context, params, scenario, where):
    """make's params over the trial's own parameters of `policy` (a path or a Policy; None: none),
    the learned skills it embeds (JSON text, "" for none), as `roger eval --policy` has them, and
    the Policy (None for none): params given win over the trial's, and another scenario than the
    stage's takes none."""
    if policy is None:
        return params, "", None
    # Found by a probe: make(..., policy=5) said "5: cannot read the policy file".
    if not isinstance(policy, (Policy, str, bytes, os.PathLike)):
        raise RogerError(f"{where}: policy is the path of a policy.json (a str or os.PathLike) or a roger.Policy, "
                         f"got {type(policy).__name__} {_short(policy)}")
    p = policy if isinstance(policy, Policy) else Policy(policy)
    if (p.stage, p.context) != (str(stage), str(context)):
        raise RogerError(f"{where}: policy {p.path} is of stage {p.stage} context {p.context}, not of stage {stage} "
                         f"context {context}: make it with policy.make(), or give the policy's stage and context")
    trial = dict(p._p.trial_params(_native(curriculum), _native(scenario or "")))
    # As roger eval notes it (found by a probe: policy.make() played a curriculum edited since,
    # or the project's copy of a name the trial's folder had its own of, without a word).
    note = p._p.curriculum_note(_native(curriculum))
    if note:
        _warn(f"{where}: {p.path}: {note}")
    given = _text_dict(params, "params")
    return {**{k: v for k, v in trial.items() if k not in given}, **given}, p._p.skills_json, p


def _check_policy_actions(p, actions, where):
    """Refuses a Policy (None: none) whose actions are not the environment's, in the same order, as
    `roger eval` refuses it: its act() indexes its own actions, so a reordered or renamed set would
    run other actions than it chose (found by a probe: 20 of 20 fell to 6 of 20)."""
    if p is None:
        return
    import json
    if p.actions != tuple(actions):
        raise RogerError(f"{where}: {p.path}: field \"actions\" is {json.dumps(list(p.actions))} but this stage's "
                         f"actions are {json.dumps(list(actions))} (a policy is tied to its action set and order)")


def load_policy(path):
    """A saved policy.json (Policy); raises RogerError naming the file and field when malformed."""
    return Policy(path)


# The paper's stages (curricula/paper.lua): search-grasp in B1, DC1, DC2 and transport in B2,
# DC3-DC6. T in DC3-DC6 reuses the learned Phi_SG: gymnasium.make("roger/T-DC6-v0",
# skills={"Phi_SG": ".../policy.json"}) with the policy of `roger train curricula/paper.lua --stage SG
# --context DC2` (as `roger run` trains T on SG/DC2's policy of the same seed).
PAPER_IDS = {f"roger/{stage}-{context}-v0": (stage, context)
             for stage, contexts in (("SG", ("B1", "DC1", "DC2")), ("T", ("B2", "DC3", "DC4", "DC5", "DC6")))
             for context in contexts}


def _register():
    registry = _gym.envs.registration.registry
    # make_vec is each id's vector entry point: gymnasium.make_vec then builds the threaded batch
    # (its default when an id has one), or single environments with vectorization_mode="sync".
    if "roger/Stage-v0" not in registry:
        _gym.register("roger/Stage-v0", entry_point="roger:Env", vector_entry_point="roger:make_vec")
    for env_id, (stage, context) in PAPER_IDS.items():
        if env_id not in registry:
            _gym.register(env_id, entry_point="roger:Env", vector_entry_point="roger:make_vec",
                          kwargs={"curriculum": "paper", "stage": stage, "context": context})


if _gym is not None:
    _register()
