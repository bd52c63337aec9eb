"""The compiled ziggurat gives numpy's standard normals bit for bit and leaves the generator
where numpy's ``standard_normal`` leaves it (the oracle is numpy itself, drawn from a twin
generator with the same seed)."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.core._normal_kernel import _pcg64, standard_normal


@pytest.mark.parametrize(("seed", "shape"), [(0, (10_000, 14, 6)), (7, 5000), (12345, (4097, 3))])
def test_numbers_and_state_equal_numpys(seed: int, shape: int | tuple[int, ...]) -> None:
    ours, theirs = np.random.default_rng(seed), np.random.default_rng(seed)
    drawn = standard_normal(ours, shape)
    expected = theirs.standard_normal(shape)
    assert drawn.shape == expected.shape
    assert np.array_equal(drawn, expected)
    assert ours.bit_generator.state == theirs.bit_generator.state
    assert np.array_equal(ours.standard_normal(100), theirs.standard_normal(100))


def test_the_tails_of_many_draws_equal_numpys() -> None:
    """4 million numbers: about 1,000 from the tail beyond 3.65 and 50,000 rejection tests."""
    drawn = standard_normal(np.random.default_rng(99), 4_000_000)
    expected = np.random.default_rng(99).standard_normal(4_000_000)
    assert (np.abs(expected) > 3.6541528853610088).sum() > 500
    assert np.array_equal(drawn, expected)


def test_the_pcg64_step_gives_numpys_raw_words() -> None:
    words = np.random.default_rng(2024).bit_generator.state["state"]
    mask = (1 << 64) - 1
    high, low = np.uint64(words["state"] >> 64), np.uint64(words["state"] & mask)
    inc = (np.uint64(words["inc"] >> 64), np.uint64(words["inc"] & mask))
    drawn = []
    for _ in range(1000):
        high, low, word = (np.uint64(x) for x in _pcg64(high, low, *inc))
        drawn.append(int(word))
    assert drawn == np.random.default_rng(2024).bit_generator.random_raw(1000).tolist()


def test_other_bit_generators_and_small_draws_are_numpys() -> None:
    ours = np.random.Generator(np.random.MT19937(5))
    theirs = np.random.Generator(np.random.MT19937(5))
    assert np.array_equal(standard_normal(ours, 10_000), theirs.standard_normal(10_000))
    small, twin = np.random.default_rng(1), np.random.default_rng(1)
    assert np.array_equal(standard_normal(small, (10, 6)), twin.standard_normal((10, 6)))
    assert small.bit_generator.state == twin.bit_generator.state
