"""RunSeeds against the streams written out as SeedSequence spawn keys (the file format)."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.core.seeds import RunSeeds
from aaria_pin.errors import ParameterError


def test_a_data_set_run_draws_each_part_from_spawn_key_run_part() -> None:
    seeds = RunSeeds(11, run=4)
    for part, name in enumerate(("structure", "joints", "base", "noise")):
        expected = np.random.default_rng(np.random.SeedSequence(11, spawn_key=(4, part)))
        assert seeds.generator(name).random() == expected.random()
    assert seeds.noise.spawn_key == (4, 3)
    assert seeds.sequence("fourier").spawn_key == (4, 1)  # a data set's Fourier: its joints


def test_a_single_run_draws_noise_from_the_seed_and_fourier_from_spawn_key_1() -> None:
    seeds = RunSeeds(11)
    assert seeds.noise == 11
    assert seeds.generator("noise").random() == np.random.default_rng(11).random()
    fourier = np.random.default_rng(np.random.SeedSequence(11, spawn_key=(1,)))
    assert seeds.generator("fourier").random() == fourier.random()


def test_a_0_1_data_set_keeps_its_noise_part() -> None:
    assert RunSeeds(2, run=7, noise_part=3).noise.spawn_key == (7, 3)


@pytest.mark.parametrize(
    ("seeds", "stream"), [(RunSeeds(1), "joints"), (RunSeeds(1, run=0), "wind")]
)
def test_an_unknown_stream_names_the_parameter(seeds: RunSeeds, stream: str) -> None:
    with pytest.raises(ParameterError) as info:
        seeds.sequence(stream)
    assert info.value.parameter == "stream"


@pytest.mark.parametrize(("seed", "run"), [(-1, None), (1, -2)])
def test_a_bad_seed_or_run_is_refused(seed: int, run: int | None) -> None:
    with pytest.raises(ParameterError):
        RunSeeds(seed, run)
