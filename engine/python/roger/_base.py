"""Gymnasium's Env and VectorEnv contracts, for when gymnasium is not installed: the attributes
(metadata, render_mode, spec, np_random, unwrapped, closed), reset's seeding of np_random, close
and the context manager, Env's get_wrapper_attr, has_wrapper_attr and set_wrapper_attr, with
gymnasium 1.x's names and behaviour, so the package's environments act the same with and without
it."""

from enum import Enum

import numpy as np


class AutoresetMode(Enum):
    """How a vector environment begins an ended episode's successor (gymnasium.vector.AutoresetMode)."""
    NEXT_STEP = "NextStep"
    SAME_STEP = "SameStep"
    DISABLED = "Disabled"


class _Seeded:
    _np_random = None
    _np_random_seed = None

    @property
    def np_random(self):
        """The learner's random generator, seeded by reset(seed=...) (made when first used);
        unseeded, from the OS."""
        if self._np_random is None:
            if self._np_random_seed is None:
                self._np_random_seed = int(np.random.SeedSequence().entropy)
            self._np_random = np.random.Generator(np.random.PCG64(np.random.SeedSequence(self._np_random_seed)))
        return self._np_random

    @np_random.setter
    def np_random(self, value):
        self._np_random, self._np_random_seed = value, -1

    @property
    def np_random_seed(self):
        self.np_random
        return self._np_random_seed

    def _seed_np_random(self, seed):
        self._np_random, self._np_random_seed = None, seed

    @property
    def unwrapped(self):
        return self

    def __enter__(self):
        return self

    def __exit__(self, *args):
        self.close()
        return False


class Env(_Seeded):
    """gymnasium.Env's contract."""
    metadata = {"render_modes": []}
    render_mode = None
    spec = None

    def reset(self, *, seed=None, options=None):
        if seed is not None:
            self._seed_np_random(seed)

    def close(self):
        pass

    # An environment is its own innermost wrapper: Gymnasium 1.x's Env looks the attribute up on itself.
    def has_wrapper_attr(self, name):
        return hasattr(self, name)

    def get_wrapper_attr(self, name):
        return getattr(self, name)

    def set_wrapper_attr(self, name, value, *, force=True):
        if force or hasattr(self, name):
            setattr(self, name, value)
            return True
        return False


class VectorEnv(_Seeded):
    """gymnasium.vector.VectorEnv's contract."""
    metadata = {}
    render_mode = None
    spec = None
    closed = False

    def reset(self, *, seed=None, options=None):
        if seed is not None:
            self._seed_np_random(seed)

    def close(self, **kwargs):
        if self.closed:
            return
        self.close_extras(**kwargs)
        self.closed = True

    def close_extras(self, **kwargs):
        pass

    def __del__(self):
        if not getattr(self, "closed", True):
            self.close()
