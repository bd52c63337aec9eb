"""DatasetSources.spec(): the rules of ``aaria dataset`` in the library (spec_sources.py)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.spec_sources import DatasetSources, spec_from_sources
from aaria_pin.apps.dataset.urdf_spec import UrdfDatasetSpec
from aaria_pin.errors import ParameterError

SHORT = {"n_runs": 2, "duration": 0.2, "seed": 3}


def test_nothing_given_varies_every_part_of_a_random_arm() -> None:
    spec = DatasetSources(**SHORT).spec()
    assert isinstance(spec, DhDatasetSpec)
    assert spec.vary == ("structure", "joints", "base") and spec.dh_table is None
    assert spec.joint_table is None and spec.base_table is None and spec.name == ""


def test_a_preset_fixes_the_structure_and_gives_its_tables() -> None:
    fig2 = get_preset("aaria-fig2")
    spec = DatasetSources(**SHORT, preset="aaria-fig2").spec()
    assert isinstance(spec, DhDatasetSpec)
    assert spec.vary == ("joints", "base") and spec.name == "aaria-fig2"
    np.testing.assert_array_equal(spec.dh_table, fig2.table)
    np.testing.assert_array_equal(spec.joint_table, fig2.joint_table)
    np.testing.assert_array_equal(spec.base_table, fig2.base_table)
    fourier = DatasetSources(**SHORT, preset="aaria-fig2", motion="fourier").spec()
    assert fourier.joint_table is None  # the excitation replaces the preset's sines
    np.testing.assert_array_equal(fourier.base_table, fig2.base_table)


def test_table_files_fix_their_parts(tmp_path: Path) -> None:
    joints = np.zeros((8, 5))
    joints[0] = [0.3, 0.0, 0.1, 1.5, 0.25]
    np.savetxt(tmp_path / "j.csv", joints, delimiter=",")
    base = np.full((6, 4), 0.01)
    np.savetxt(tmp_path / "b.csv", base, delimiter=",")
    spec = spec_from_sources(
        DatasetSources(**SHORT, joints_file=tmp_path / "j.csv", base_file=tmp_path / "b.csv")
    )
    assert spec.vary == ("structure",)
    np.testing.assert_array_equal(spec.joint_table, joints)
    np.testing.assert_array_equal(spec.base_table, base)
    both = spec_from_sources(DatasetSources(**SHORT, vary=["base"], preset="aaria-fig2"))
    assert both.vary == ("base",)
    spaced = spec_from_sources(DatasetSources(**SHORT, vary=" structure , base,"))
    assert spaced.vary == ("structure", "base")


def test_the_spec_of_sources_makes_the_runs_of_the_spec_written_out() -> None:
    fig2 = get_preset("aaria-fig2")
    made = DatasetSources(**SHORT, preset="aaria-fig2").spec()
    direct = DhDatasetSpec(
        **SHORT,
        vary=("joints", "base"),
        dh_table=fig2.table,
        joint_table=fig2.joint_table,
        base_table=fig2.base_table,
        name="aaria-fig2",
    )
    assert made.attributes() == direct.attributes()
    for name, array in direct.arrays(1).items():
        np.testing.assert_array_equal(made.arrays(1)[name], array, err_msg=name)


def test_a_urdf_robot_varies_its_motions_its_base_unless_fixed() -> None:
    moving = spec_from_sources(DatasetSources(**SHORT, robot="ur5"))
    assert isinstance(moving, UrdfDatasetSpec) and moving.vary == ("joints", "base")
    assert moving.source.moving_base and moving.source.source == "ur5"
    fixed = spec_from_sources(DatasetSources(**SHORT, robot="ur5", fixed_base=True))
    assert isinstance(fixed, UrdfDatasetSpec) and fixed.vary == ("joints",)
    assert not fixed.source.moving_base
    assert "base_table" not in fixed.layout().tables


@pytest.mark.parametrize(
    ("sources", "parameter", "pattern"),
    [
        ({"convention": "standard"}, "convention", "allowed: aaria"),
        ({"robot": "ur5", "preset": "aaria-fig2"}, "robot", "not both"),
        ({"preset": "aaria-fig2", "dh_file": "t.csv"}, "dh_table", "give a preset or a DH"),
        ({"preset": "spherical-wrist"}, "preset", "allowed: aaria-*"),
        ({"tool_frame": "tool0"}, "tool_frame", "needs --robot or --urdf"),
        ({"imu_layout_file": "imus.toml"}, "imu_layout_file", "needs --robot or --urdf"),
        ({"fixed_base": True}, "fixed_base", "needs --robot or --urdf"),
        ({"vary": "joints"}, "dh_table", "needs --preset or --dh"),
        ({"preset": "aaria-fig2", "vary": "structure"}, "vary", "a fixed structure table"),
        ({"robot": "ur5", "fixed_base": True, "vary": "base"}, "vary", "base cannot vary"),
        ({"robot": "ur5", "vary": "structure"}, "vary", "structure is fixed"),
        ({"robot": "ur5", "urdf_file": "x.urdf"}, "urdf_file", "not both"),
        ({"vary": "colour"}, "vary", "a part of vary is 'colour'"),
    ],
)
def test_sources_no_data_set_can_use_are_refused_naming_the_parameter(
    sources: dict[str, object], parameter: str, pattern: str
) -> None:
    with pytest.raises(ParameterError, match=pattern.replace("*", r"\*")) as refused:
        spec_from_sources(DatasetSources(**SHORT, **sources))  # type: ignore[arg-type]
    assert refused.value.parameter == parameter


def test_a_base_table_on_a_fixed_base_is_refused(tmp_path: Path) -> None:
    np.savetxt(tmp_path / "b.csv", np.zeros((6, 4)), delimiter=",")
    with pytest.raises(ParameterError, match="not allowed with --fixed-base") as refused:
        spec_from_sources(
            DatasetSources(**SHORT, robot="ur5", fixed_base=True, base_file=tmp_path / "b.csv")
        )
    assert refused.value.parameter == "base_table"
