"""``aaria template``: every template reads back through the commands' readers and simulates."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest
from click.testing import CliRunner

from aaria_pin.aaria.presets import get_preset
from aaria_pin.cli._app import main
from aaria_pin.cli.template_cmd import KINDS, template

PAPER_TABLE_3 = np.array(  # the paper's Table 3 (Figure 2 arm), typed from the paper
    [
        [np.pi / 2, 0.89, 0.0, 0.14, 2],
        [np.pi / 2, 0.83, np.pi / 2, 0.29, 1],
        [np.pi / 2, 0.88, 0.0, 0.22, 1],
        [np.pi / 2, 0.85, np.pi / 2, 0.24, 1],
        [0.0, 0.86, np.pi / 2, 0.13, 2],
        [0.0, 0.89, 0.0, 0.23, 1],
        [np.pi / 2, 0.89, np.pi / 2, 0.12, 1],
        [-np.pi / 2, 0.86, 0.0, 0.29, 1],
    ]
)


def _write(folder: Path, kind: str, name: str) -> Path:
    result = CliRunner().invoke(template, [kind, "-o", str(folder / name)])
    assert result.exit_code == 0, result.output
    return folder / name


def test_the_kinds_are_the_library_templates() -> None:
    from aaria_pin.aaria.templates import TEMPLATE_KINDS

    assert KINDS == TEMPLATE_KINDS


def test_every_template_is_commented_and_printed() -> None:
    for kind in KINDS:
        result = CliRunner().invoke(template, [kind])
        assert result.exit_code == 0
        lines = result.output.splitlines()
        assert sum(line.startswith("#") for line in lines) >= 5, kind
    assert "ADIS16485" in CliRunner().invoke(template, ["config"]).output


def test_the_table_templates_simulate_through_the_command(tmp_path: Path) -> None:
    from aaria_pin.files.io import read_table

    dh = _write(tmp_path, "dh", "dh.csv")
    joints = _write(tmp_path, "joints", "joints.csv")
    base = _write(tmp_path, "base", "base.csv")
    np.testing.assert_array_equal(read_table(dh), PAPER_TABLE_3)
    np.testing.assert_array_equal(read_table(dh), get_preset("aaria-fig2").table)
    np.testing.assert_array_equal(
        read_table(base, "senSenB"), [[0.05, 0, 1, 0], [0.05, 0, 0.7, 0.3]]
    )
    args = ["simulate", "--dh", str(dh), "--joints", str(joints), "--base", str(base)]
    args += ["--duration", "0.2", "-o", str(tmp_path / "run.h5")]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    with h5py.File(tmp_path / "run.h5", "r") as handle:
        names: list[str] = []
        handle.visit(names.append)
        q = handle[next(n for n in names if n.split("/")[-1] == "q")][()]
    # module 2 (revolute) follows the template's row 2: 0.6 sin(1.4 t + 1.0), no bias
    time = np.arange(q.shape[0]) / 100.0
    np.testing.assert_allclose(q[:, 1], 0.6 * np.sin(1.4 * time + 1.0), atol=1e-12)


def test_the_imu_layout_template_simulates_ur5(tmp_path: Path) -> None:
    layout = _write(tmp_path, "imu-layout", "imus.toml")
    args = ["simulate", "--robot", "ur5", "--imu-layout", str(layout), "--duration", "0.1"]
    result = CliRunner().invoke(main, [*args, "-o", str(tmp_path / "run.h5")])
    assert result.exit_code == 0, result.output
    from aaria_pin.files.runfile import read_run

    run = read_run(tmp_path / "run.h5")
    assert [m.name for m in run.imu_mounts] == ["imu_base", "imu_forearm", "imu_wrist"]
    assert run.imu.shape[1:] == (3, 6)


def test_the_config_template_is_the_default_configuration(tmp_path: Path) -> None:
    from aaria_pin.aaria.randomize import RandomConfig, random_dh_table
    from aaria_pin.aaria.simulate import simulate_run
    from aaria_pin.apps.dataset.config import load_dataset_config
    from aaria_pin.core.imu_noise import ADIS16485
    from aaria_pin.core.seeds import RunSeeds

    config, hardware = load_dataset_config(_write(tmp_path, "config", "ranges.toml"))
    assert config == RandomConfig()
    assert hardware.nominal(0).imu == ADIS16485  # the [imu] tables: the data sheet's values
    assert hardware.nominal(0).encoder is None  # no joint hardware unless given
    table = random_dh_table(config, RunSeeds(0, 0).generator("structure"))
    assert simulate_run(table, duration=0.05).imu.shape == (6, 14, 6)


def test_an_existing_file_is_kept_unless_overwrite(tmp_path: Path) -> None:
    path = tmp_path / "dh.csv"
    path.write_text("my edited arm")
    result = CliRunner().invoke(template, ["dh", "-o", str(path)])
    assert result.exit_code != 0 and path.read_text() == "my edited arm"
    result = CliRunner().invoke(template, ["dh", "-o", str(path), "--overwrite"])
    assert result.exit_code == 0 and path.read_text().startswith("# Extended DH table")


@pytest.mark.parametrize("kind", ["urdf", ""])
def test_an_unknown_kind_is_a_usage_error(kind: str) -> None:
    result = CliRunner().invoke(template, [kind])
    assert result.exit_code == 2 and "dh|joints|base|imu-layout|config" in result.output
