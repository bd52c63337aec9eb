from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from aaria_pin.aaria.dh import chain_from_aaria
from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.aaria.randomize import (
    PARTS,
    RandomConfig,
    default_config_toml,
    load_config,
    random_base_table,
    random_dh_table,
    random_joint_table,
    refuse_unknown_keys,
)
from aaria_pin.aaria.sine_tables import validate_base_table, validate_joint_table
from aaria_pin.core.model import build_model
from aaria_pin.core.seeds import DATASET_STREAMS, RunSeeds
from aaria_pin.errors import InputFileError, ParameterError

CONFIG = RandomConfig()


@pytest.mark.slow
def test_thousands_of_draws_are_valid_and_in_range() -> None:
    types = np.zeros(3, dtype=int)
    for run in range(3000):
        structure, joints, base = (RunSeeds(11, run).generator(p) for p in PARTS)
        table = random_dh_table(CONFIG, structure)
        chain = chain_from_aaria(table)  # validates the table
        for row in range(6):
            types[int(table[row, 4])] += 1
            if table[row, 4]:
                assert 0.8 <= table[row, 1] <= 0.9 and 0.1 <= table[row, 3] <= 0.3
                assert table[row, 0] in CONFIG.alpha_choices
        validate_joint_table(random_joint_table(CONFIG, table, joints), chain)
        validate_base_table(random_base_table(CONFIG, base))
        if run % 10 == 0:  # a URDF that Pinocchio loads, for a sample of them
            robot = build_dh_robot(table)
            assert build_model(robot.urdf, moving_base=True).n_joints == len(chain.joints)
    assert np.all(types > 4000)  # each link type drawn about a third of the time


def test_streams_depend_only_on_seed_and_run() -> None:
    a = [RunSeeds(5, 17).generator(part).random(3) for part in DATASET_STREAMS]
    b = [RunSeeds(5, 17).generator(part).random(3) for part in DATASET_STREAMS]
    c = [RunSeeds(5, 18).generator(part).random(3) for part in DATASET_STREAMS]
    for x, y, z in zip(a, b, c, strict=True):
        np.testing.assert_array_equal(x, y)
        assert not np.array_equal(x, z)
    assert not np.array_equal(a[0], a[1])


def test_the_parts_are_the_first_streams_of_a_data_set_run() -> None:
    assert PARTS == ("structure", "joints", "base")
    for part, name in enumerate(DATASET_STREAMS):  # the spawn keys every data set since 0.2 used
        seeded = np.random.Generator(
            np.random.PCG64(np.random.SeedSequence(5, spawn_key=(17, part)))
        ).random(4)
        np.testing.assert_array_equal(RunSeeds(5, 17).generator(name).random(4), seeded)


def test_prismatic_motion_stays_on_its_rail_at_the_extremes() -> None:
    config = RandomConfig(
        link_type_probabilities=(0.0, 0.0, 1.0),
        prismatic_amplitude_fraction=(0.45, 0.45),
        prismatic_bias_fraction=(1.0, 1.0),
    )
    rng = np.random.default_rng(0)
    for _ in range(50):
        table = random_dh_table(config, rng)
        validate_joint_table(random_joint_table(config, table, rng), chain_from_aaria(table))


def test_default_config_prints_and_reads_back(tmp_path: Path) -> None:
    path = tmp_path / "ranges.toml"
    path.write_text(default_config_toml())
    assert load_config(path) == CONFIG
    path.write_text("a = [0.5, 0.6]\nbase_per_axis = false\n")
    config = load_config(path)
    assert config.a == (0.5, 0.6) and config.base_per_axis is False and config.d == CONFIG.d


@pytest.mark.parametrize(
    ("text", "pattern"),
    [
        ("speed = [1, 2]\n", "unknown key 'speed'"),
        ("a = [0.9, 0.8]\n", r"config a is \(0.9, 0.8\); allowed: a range \[low, high\]"),
        ("alpha_choices = []\n", "alpha_choices is empty"),
        ("link_type_probabilities = [1, 0, 0]\n", "revolute \\+ prismatic > 0"),
        ("prismatic_amplitude_fraction = [0.1, 0.8]\n", "within \\[0, 0.5\\]"),
        ("a = [0.8\n", "not valid TOML"),
    ],
)
def test_bad_configs(tmp_path: Path, text: str, pattern: str) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises((ParameterError, InputFileError), match=pattern):
        load_config(path)


def test_missing_config_file(tmp_path: Path) -> None:
    with pytest.raises(InputFileError, match="cannot be read"):
        load_config(tmp_path / "nope.toml")


def test_refuse_unknown_keys_names_the_first_unknown_key_and_the_known_ones() -> None:
    refuse_unknown_keys({"b": 1}, ["b", "a"], "config: noise")  # all known: no error
    with pytest.raises(ParameterError) as caught:
        refuse_unknown_keys({"z": 1, "b": 2, "y": 3}, ["b", "a"], "config: noise")
    assert str(caught.value) == "config: noise: unknown key 'y'; allowed: b, a"
    assert (caught.value.parameter, caught.value.value, caught.value.element) == (
        "config",
        "y",
        "config: noise",
    )
