"""The few Gymnasium spaces roger's environments use, for when gymnasium is not installed: the same
names, attributes (n, start, nvec, shape, dtype, low, high, spaces) and methods (sample, contains,
seed), following gymnasium 1.x's own code (1.4: gymnasium/spaces/), so that a space seeded alike
samples the same values with or without gymnasium, and holds the same members."""

from collections.abc import Mapping, Sequence

import numpy as np


def _np_random(seed=None):
    """gymnasium.utils.seeding.np_random: a generator and the seed it was made from (drawn from the
    operating system when None)."""
    if seed is not None and not (isinstance(seed, int) and seed >= 0):
        raise ValueError(f"a space's seed is a non-negative Python int, got {seed!r}")
    seed_seq = np.random.SeedSequence(seed)
    return np.random.Generator(np.random.PCG64(seed_seq)), seed_seq.entropy


class Space:
    def __init__(self, shape, dtype, seed=None):
        self._shape = None if shape is None else tuple(shape)
        self.dtype = None if dtype is None else np.dtype(dtype)
        self._np_random = None
        if seed is not None:
            if isinstance(seed, np.random.Generator):
                self._np_random = seed
            else:
                self.seed(seed)

    @property
    def shape(self):
        return self._shape

    @property
    def np_random(self):
        """The space's generator, made when first used (unseeded: from the operating system)."""
        if self._np_random is None:
            self.seed()
        if self._np_random is None:  # a composite space seeds its parts, not itself
            self._np_random, _ = _np_random()
        return self._np_random

    def seed(self, seed=None):
        """Seeds the space's generator; returns the seed it was made from."""
        self._np_random, seed = _np_random(seed)
        return seed

    def __contains__(self, x):
        return self.contains(x)


class Discrete(Space):
    def __init__(self, n, seed=None, start=0, dtype=np.int64):
        self.dtype = np.dtype(dtype)
        self.n = self.dtype.type(n)
        self.start = self.dtype.type(start)
        super().__init__((), self.dtype, seed)

    def sample(self):
        return self.start + self.np_random.integers(self.n, dtype=self.dtype.type)

    def contains(self, x):
        # A Python int (in the dtype's range), or a numpy integer scalar or 0-d integer array.
        if isinstance(x, int):
            info = np.iinfo(self.dtype)
            if not info.min <= x <= info.max:
                return False
            x = self.dtype.type(x)
        elif not (isinstance(x, (np.generic, np.ndarray)) and np.issubdtype(x.dtype, np.integer) and x.shape == ()):
            return False
        return bool(int(self.start) <= int(x) < int(self.start) + int(self.n)) and np.can_cast(x.dtype, self.dtype)

    def __repr__(self):
        return f"Discrete({self.n})" if self.start == 0 else f"Discrete({self.n}, start={self.start})"


class MultiDiscrete(Space):
    def __init__(self, nvec, dtype=np.int64, seed=None, start=None):
        self.nvec = np.array(nvec, dtype=dtype, copy=True)
        self.start = np.zeros(self.nvec.shape, dtype) if start is None else np.array(start, dtype=dtype, copy=True)
        super().__init__(self.nvec.shape, dtype, seed)

    def sample(self):
        return (self.np_random.random(self.nvec.shape) * self.nvec).astype(self.dtype) + self.start

    def contains(self, x):
        # A list or tuple is taken as an array; an array's dtype must cast to the space's safely.
        if isinstance(x, Sequence):
            x = np.array(x)
        return bool(isinstance(x, np.ndarray) and x.shape == self.shape and np.can_cast(x.dtype, self.dtype)
                    and np.all(self.start <= x) and np.all(x <= self.start + (self.nvec - 1)))

    def __repr__(self):
        return f"MultiDiscrete({self.nvec})"


class Box(Space):
    def __init__(self, low, high, shape=None, dtype=np.float32, seed=None):
        dtype = np.dtype(dtype)
        if shape is not None:
            shape = tuple(int(d) for d in shape)
        elif isinstance(low, np.ndarray) and isinstance(high, np.ndarray):
            if low.shape != high.shape:
                raise ValueError(f"Box low.shape and high.shape don't match, low.shape={low.shape}, "
                                 f"high.shape={high.shape}")
            shape = low.shape
        elif isinstance(low, np.ndarray):
            shape = low.shape
        elif isinstance(high, np.ndarray):
            shape = high.shape
        else:
            shape = (1,)  # low and high are scalars
        self.dtype = dtype
        self.low, self.bounded_below = self._bound(low, shape, -1)
        self.high, self.bounded_above = self._bound(high, shape, 1)
        if self.low.shape != shape or self.high.shape != shape:
            raise ValueError(f"Box low.shape {self.low.shape} and high.shape {self.high.shape} must be {shape}")
        super().__init__(shape, dtype, seed)

    def _bound(self, value, shape, side):
        """A bound as an array of the dtype, and where it is finite (an infinite bound of a signed
        integer Box is the dtype's end)."""
        value = np.array(value)
        finite = np.isfinite(value) if value.dtype.kind == "f" else np.ones(value.shape, bool)
        if self.dtype.kind == "i" and not finite.all():
            value = np.where(finite, value, np.iinfo(self.dtype).max if side > 0 else np.iinfo(self.dtype).min)
        if value.ndim == 0:
            value, finite = np.full(shape, value), np.full(shape, finite)
        return value.astype(self.dtype), finite

    def is_bounded(self, manner="both"):
        below, above = bool(np.all(self.bounded_below)), bool(np.all(self.bounded_above))
        return {"both": below and above, "below": below, "above": above}[manner]

    def sample(self):
        # Uniform within finite bounds (integers: floor of [low, high + 1)), exponential from a
        # single finite bound, normal without either, as gymnasium's Box samples.
        high = self.high if self.dtype.kind == "f" else self.high.astype("int64") + 1
        sample = np.empty(self.shape)
        unbounded = ~self.bounded_below & ~self.bounded_above
        upp_bounded = ~self.bounded_below & self.bounded_above
        low_bounded = self.bounded_below & ~self.bounded_above
        bounded = self.bounded_below & self.bounded_above
        sample[unbounded] = self.np_random.normal(size=unbounded[unbounded].shape)
        sample[low_bounded] = self.np_random.exponential(size=low_bounded[low_bounded].shape) + self.low[low_bounded]
        sample[upp_bounded] = -self.np_random.exponential(size=upp_bounded[upp_bounded].shape) + high[upp_bounded]
        sample[bounded] = self.np_random.uniform(low=self.low[bounded], high=high[bounded],
                                                 size=bounded[bounded].shape)
        if self.dtype.kind in "iub":
            sample = np.floor(sample)
        return sample.astype(self.dtype)

    def contains(self, x):
        if not isinstance(x, np.ndarray):
            try:
                x = np.asarray(x, dtype=self.dtype)
            except (ValueError, TypeError, OverflowError):
                return False
        return bool(np.can_cast(x.dtype, self.dtype) and x.shape == self.shape
                    and np.all(x >= self.low) and np.all(x <= self.high))

    def __repr__(self):
        low = self.low.flat[0] if self.low.size and np.all(self.low == self.low.flat[0]) else self.low
        high = self.high.flat[0] if self.high.size and np.all(self.high == self.high.flat[0]) else self.high
        return f"Box({low}, {high}, {self.shape}, {self.dtype})"


class Dict(Space):
    def __init__(self, spaces=None, seed=None, **spaces_kwargs):
        # Sorted by key, as gymnasium keeps a mapping's spaces (a list of pairs keeps its order).
        if isinstance(spaces, Mapping):
            try:
                spaces = dict(sorted(spaces.items()))
            except TypeError:
                spaces = dict(spaces.items())
        self.spaces = dict(spaces or {})
        for key, space in spaces_kwargs.items():
            if key in self.spaces:
                raise ValueError(f"Dict space keyword '{key}' already exists in the spaces dictionary.")
            self.spaces[key] = space
        super().__init__(None, None, seed)

    def seed(self, seed=None):
        """Seeds every subspace: None each from the operating system, an int through this space's
        generator (one seed drawn per subspace, as gymnasium does), a dict one seed per key.
        Returns each subspace's seed by key."""
        if seed is None:
            return {k: s.seed(None) for k, s in self.spaces.items()}
        if isinstance(seed, int):
            super().seed(seed)
            subseeds = self.np_random.integers(np.iinfo(np.int32).max, size=len(self.spaces))
            return {k: s.seed(int(sub)) for (k, s), sub in zip(self.spaces.items(), subseeds)}
        if isinstance(seed, dict):
            if seed.keys() != self.spaces.keys():
                raise ValueError(f"The seed keys: {seed.keys()} are not identical to space keys: "
                                 f"{self.spaces.keys()}")
            return {k: self.spaces[k].seed(seed[k]) for k in seed}
        raise TypeError(f"Expected seed type: dict, int or None, actual type: {type(seed)}")

    def __getitem__(self, key):
        return self.spaces[key]

    def keys(self):
        return self.spaces.keys()

    def __iter__(self):
        return iter(self.spaces)

    def __len__(self):
        return len(self.spaces)

    def sample(self):
        return {k: s.sample() for k, s in self.spaces.items()}

    def contains(self, x):
        return isinstance(x, dict) and x.keys() == self.spaces.keys() and all(
            x[k] in s for k, s in self.spaces.items())

    def __repr__(self):
        return "Dict(" + ", ".join(f"{k!r}: {s}" for k, s in self.spaces.items()) + ")"
