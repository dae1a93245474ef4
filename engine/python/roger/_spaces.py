"""The few Gymnasium spaces roger's environments use, for when gymnasium is not installed: the same
names, attributes (n, start, nvec, shape, dtype, low, high, spaces) and methods (sample with its
mask and probability, contains, seed, ==, to_jsonable and from_jsonable), following gymnasium 1.x's
own code (1.4: gymnasium/spaces/), so that a space seeded alike samples the same values with or
without gymnasium, holds the same members and equals the same spaces."""

from collections.abc import Mapping, Sequence

import numpy as np


def _np_random(seed=None):
    """gymnasium.utils.seeding.np_random: a generator and the seed it was made from (drawn from the
    operating system when None)."""
    if seed is not None and not (isinstance(seed, int) and seed >= 0):
        raise ValueError(f"a space's seed is a non-negative Python int, got {seed!r}")
    seed_seq = np.random.SeedSequence(seed)
    return np.random.Generator(np.random.PCG64(seed_seq)), seed_seq.entropy


class Error(Exception):
    """gymnasium.error.Error: what Box.sample raises for a mask."""


def _one_of(mask, probability):
    if mask is not None and probability is not None:
        raise ValueError(f"Only one of `mask` or `probability` can be provided, actual values: mask={mask}, "
                         f"probability={probability}")


def _masked_choice(np_random, sub_mask, n, start, kind):
    """One value of an axis of n values from `start`, drawn as gymnasium draws it under a mask (int8
    0/1: uniform among the 1s, `start` when none) or a probability mask (float64 summing to 1)."""
    assert isinstance(sub_mask, np.ndarray), f"The expected type of the sample {kind} is np.ndarray, actual type: " \
        f"{type(sub_mask)}"
    assert len(sub_mask) == n, f"The expected length of the sample {kind} is {int(n)}, actual length: {len(sub_mask)}"
    if kind == "mask":
        assert sub_mask.dtype == np.int8, f"The expected dtype of the sample mask is np.int8, actual dtype: " \
            f"{sub_mask.dtype}"
        valid = sub_mask == 1
        assert np.all(np.logical_or(sub_mask == 0, valid)), f"All values of the sample mask should be 0 or 1, " \
            f"actual values: {sub_mask}"
        return np_random.choice(np.where(valid)[0]) + start if np.any(valid) else start
    assert sub_mask.dtype == np.float64, f"The expected dtype of the sample probability is np.float64, actual " \
        f"dtype: {sub_mask.dtype}"
    valid = np.logical_and(sub_mask > 0, sub_mask <= 1)
    assert np.all(np.logical_or(sub_mask == 0, valid)), f"All values of the sample probability should be between " \
        f"0 and 1, actual values: {sub_mask}"
    assert np.isclose(np.sum(sub_mask), 1), f"The sum of the sample probability should be equal to 1, actual sum: " \
        f"{np.sum(sub_mask)}"
    return np_random.choice(np.where(valid)[0], p=(sub_mask / np.sum(sub_mask))[valid]) + start


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

    def to_jsonable(self, sample_n):
        """A batch of samples as JSON-able values."""
        return list(sample_n)

    def from_jsonable(self, sample_n):
        """A batch of samples from their JSON-able values."""
        return sample_n


class Discrete(Space):
    def __init__(self, n, seed=None, start=0, dtype=np.int64):
        if not np.issubdtype(type(n), np.integer):
            raise TypeError(f"Expects `n` to be an integer, actual dtype: {type(n)}")
        if n <= 0:
            raise ValueError(f"n (counts) have to be positive, actual value: {n}")
        if not np.issubdtype(type(start), np.integer):
            raise TypeError(f"Expects `start` to be an integer, actual type: {type(start)}")
        self.dtype = np.dtype(dtype)
        self.n = self.dtype.type(n)
        self.start = self.dtype.type(start)
        super().__init__((), self.dtype, seed)

    def sample(self, mask=None, probability=None):
        """A value drawn uniformly; with `mask` (int8 of n, 1 allowed) among those allowed (start when
        none is); with `probability` (float64 of n, summing to 1) by it: as gymnasium's Discrete."""
        _one_of(mask, probability)
        if mask is not None:
            assert isinstance(mask, np.ndarray), f"The expected type of the sample mask is np.ndarray, actual type: " \
                f"{type(mask)}"
            assert mask.dtype == np.int8, f"The expected dtype of the sample mask is np.int8, actual dtype: {mask.dtype}"
            assert mask.shape == (self.n,), f"The expected shape of the sample mask is {(int(self.n),)}, actual " \
                f"shape: {mask.shape}"
            valid = mask == 1
            assert np.all(np.logical_or(mask == 0, valid)), f"All values of the sample mask should be 0 or 1, " \
                f"actual values: {mask}"
            return self.start + self.dtype.type(self.np_random.choice(np.where(valid)[0])) if np.any(valid) \
                else self.start
        if probability is not None:
            assert isinstance(probability, np.ndarray), f"The expected type of the sample probability is " \
                f"np.ndarray, actual type: {type(probability)}"
            assert probability.dtype == np.float64, f"The expected dtype of the sample probability is np.float64, " \
                f"actual dtype: {probability.dtype}"
            assert probability.shape == (self.n,), f"The expected shape of the sample probability is " \
                f"{(int(self.n),)}, actual shape: {probability.shape}"
            assert np.all(np.logical_and(probability >= 0, probability <= 1)), f"All values of the sample " \
                f"probability should be between 0 and 1, actual values: {probability}"
            assert np.isclose(np.sum(probability), 1), f"The sum of the sample probability should be equal to 1, " \
                f"actual sum: {np.sum(probability)}"
            return self.start + self.np_random.choice(np.arange(self.n, dtype=self.dtype), p=probability)
        return self.start + self.np_random.integers(self.n, dtype=self.dtype.type)

    def __eq__(self, other):
        return isinstance(other, Discrete) and self.n == other.n and self.start == other.start \
            and self.dtype == other.dtype

    def to_jsonable(self, sample_n):
        return [int(x) for x in sample_n]

    def from_jsonable(self, sample_n):
        return [self.dtype.type(x) for x in sample_n]

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
        if self.start.shape != self.nvec.shape:
            raise ValueError(f"start and nvec (counts) should have the same shape, got {self.start.shape} and "
                             f"{self.nvec.shape}")
        if not (self.nvec > 0).all():
            raise ValueError("nvec (counts) have to be positive")
        super().__init__(self.nvec.shape, dtype, seed)

    def sample(self, mask=None, probability=None):
        """A vector drawn uniformly; with `mask` or `probability`, a tuple of one int8 mask (or float64
        probabilities) per axis, nested as nvec is: as gymnasium's MultiDiscrete."""
        _one_of(mask, probability)
        if mask is not None or probability is not None:
            kind = "mask" if mask is not None else "probability"
            return np.array(self._apply_mask(mask if mask is not None else probability, self.nvec, self.start, kind),
                            dtype=self.dtype)
        return (self.np_random.random(self.nvec.shape) * self.nvec).astype(self.dtype) + self.start

    def _apply_mask(self, sub_mask, sub_nvec, sub_start, kind):
        if isinstance(sub_nvec, np.ndarray):
            assert isinstance(sub_mask, tuple), f"Expects the mask to be a tuple for sub_nvec ({sub_nvec}), actual " \
                f"type: {type(sub_mask)}"
            assert len(sub_mask) == len(sub_nvec), f"Expects the mask length to be equal to the number of actions, " \
                f"mask length: {len(sub_mask)}, nvec length: {len(sub_nvec)}"
            return [self._apply_mask(m, n, s, kind) for m, n, s in zip(sub_mask, sub_nvec, sub_start)]
        return _masked_choice(self.np_random, sub_mask, sub_nvec, sub_start, kind)

    def __eq__(self, other):
        return bool(isinstance(other, MultiDiscrete) and self.dtype == other.dtype and self.shape == other.shape
                    and np.all(self.nvec == other.nvec) and np.all(self.start == other.start))

    def to_jsonable(self, sample_n):
        return [sample.tolist() for sample in sample_n]

    def from_jsonable(self, sample_n):
        return [np.array(sample, dtype=self.dtype) for sample in sample_n]

    def contains(self, x):
        # A list or tuple is taken as an array; an array's dtype must cast to the space's safely.
        if isinstance(x, Sequence):
            x = np.array(x)
        return bool(isinstance(x, np.ndarray) and x.shape == self.shape and np.can_cast(x.dtype, self.dtype)
                    and np.all(self.start <= x) and np.all(x <= self.start + (self.nvec - 1)))

    def __repr__(self):
        if np.any(self.start != 0):
            return f"MultiDiscrete({self.nvec}, start={self.start})"
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
        if np.any(self.low > self.high):
            raise ValueError(f"Box all low values must be less than or equal to high (some values break this), "
                             f"low={self.low}, high={self.high}")
        super().__init__(shape, dtype, seed)

    def _bound(self, value, shape, side):
        """A bound as an array of the dtype, and where it is finite (an infinite bound of a signed
        integer Box is the dtype's end)."""
        value = np.array(value)
        if value.dtype.kind == "f" and np.any(np.isnan(value)):
            raise ValueError(f"No {'high' if side > 0 else 'low'} value can be equal to `np.nan`, "
                             f"{'high' if side > 0 else 'low'}={value}")
        finite = np.isfinite(value) if value.dtype.kind == "f" else np.ones(value.shape, bool)
        if self.dtype.kind == "i" and not finite.all():
            value = np.where(finite, value, np.iinfo(self.dtype).max if side > 0 else np.iinfo(self.dtype).min)
        if value.ndim == 0:
            value, finite = np.full(shape, value), np.full(shape, finite)
        return value.astype(self.dtype), finite

    def is_bounded(self, manner="both"):
        below, above = bool(np.all(self.bounded_below)), bool(np.all(self.bounded_above))
        return {"both": below and above, "below": below, "above": above}[manner]

    def sample(self, mask=None, probability=None):
        if mask is not None:
            raise Error(f"Box.sample cannot be provided a mask, actual value: {mask}")
        if probability is not None:
            raise Error(f"Box.sample cannot be provided a probability mask, actual value: {probability}")
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
        if np.issubdtype(self.dtype, np.integer):  # clipped to the dtype, as gymnasium clips
            info = np.iinfo(self.dtype)
            margin = 2 if self.dtype == np.int64 else 0
            sample = sample.clip(min=info.min + margin, max=info.max - margin)
        sample = sample.astype(self.dtype)
        if self.dtype == np.int64:
            sample = sample.clip(min=self.low, max=self.high)
        return sample

    def contains(self, x):
        if not isinstance(x, np.ndarray):
            try:
                x = np.asarray(x, dtype=self.dtype)
            except (ValueError, TypeError, OverflowError):
                return False
        return bool(np.can_cast(x.dtype, self.dtype) and x.shape == self.shape
                    and np.all(x >= self.low) and np.all(x <= self.high))

    def __eq__(self, other):
        return isinstance(other, Box) and self.shape == other.shape and self.dtype == other.dtype \
            and np.allclose(self.low, other.low) and np.allclose(self.high, other.high)

    def to_jsonable(self, sample_n):
        return [sample.tolist() for sample in sample_n]

    def from_jsonable(self, sample_n):
        return [np.asarray(sample, dtype=self.dtype) for sample in sample_n]

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
        for key, space in self.spaces.items():
            if not isinstance(space, Space):
                raise TypeError(f"Dict space element is not an instance of Space: key='{key}', space={space}")
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

    def sample(self, mask=None, probability=None):
        """A sample of every subspace; `mask` or `probability` a dict of each one's, by key."""
        _one_of(mask, probability)
        for given, what in ((mask, "mask"), (probability, "probability")):
            if given is not None:
                assert isinstance(given, dict), f"Expected sample {what} to be a dict, actual type: {type(given)}"
                assert given.keys() == self.spaces.keys(), f"Expected sample {what} keys to be same as space keys, " \
                    f"{what} keys: {given.keys()}, space keys: {self.spaces.keys()}"
                return {k: s.sample(**{what: given[k]}) for k, s in self.spaces.items()}
        return {k: s.sample() for k, s in self.spaces.items()}

    def __eq__(self, other):
        return isinstance(other, Dict) and self.spaces == other.spaces

    def to_jsonable(self, sample_n):
        return {key: space.to_jsonable([sample[key] for sample in sample_n]) for key, space in self.spaces.items()}

    def from_jsonable(self, sample_n):
        columns = {key: space.from_jsonable(sample_n[key]) for key, space in self.spaces.items()}
        n = len(next(iter(columns.values())))
        return [{key: value[i] for key, value in columns.items()} for i in range(n)]

    def contains(self, x):
        return isinstance(x, dict) and x.keys() == self.spaces.keys() and all(
            x[k] in s for k, s in self.spaces.items())

    def __repr__(self):
        return "Dict(" + ", ".join(f"{k!r}: {s}" for k, s in self.spaces.items()) + ")"
