"""The compiled ziggurat gives numpy's standard normals bit for bit and leaves the generator
where numpy's ``standard_normal`` leaves it (the oracle is numpy itself, drawn from a twin
generator with the same seed)."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.core._normal_kernel import _tables, _ziggurat, standard_normal


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


def test_words_running_out_mid_number_continue_exactly() -> None:
    """Fed a few words at a time, the kernel stops before an unfinished number and resumes."""
    raw = np.random.default_rng(3).bit_generator.random_raw(60_000)
    expected = np.random.default_rng(3).standard_normal(50_000)
    out = np.empty(50_000)
    filled, used, offset = 0, 0, 0
    while filled < out.size:
        offset += used
        filled, used = _ziggurat(raw[offset : offset + 7], out, filled, *_tables())
    assert np.array_equal(out, expected)


def test_other_bit_generators_and_small_draws_are_numpys() -> None:
    ours, theirs = np.random.Generator(np.random.MT19937(5)), np.random.Generator(np.random.MT19937(5))
    assert np.array_equal(standard_normal(ours, 10_000), theirs.standard_normal(10_000))
    small, twin = np.random.default_rng(1), np.random.default_rng(1)
    assert np.array_equal(standard_normal(small, (10, 6)), twin.standard_normal((10, 6)))
    assert small.bit_generator.state == twin.bit_generator.state
