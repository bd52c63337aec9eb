"""The public API of ``aaria_pin``: every name resolves, lazily, to its module's object."""

from __future__ import annotations

import importlib
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import aaria_pin


def test_every_public_name_resolves_to_its_module_object() -> None:
    for name in aaria_pin.__all__:
        value = getattr(aaria_pin, name)
        if name in aaria_pin._LAZY:
            assert value is getattr(importlib.import_module(aaria_pin._LAZY[name]), name)


def test_import_is_light() -> None:
    code = (
        "import sys, aaria_pin; "
        "print(sorted(m for m in ('pinocchio', 'h5py', 'scipy', 'numba') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_readme_python_example_round_trip(tmp_path: Path) -> None:
    record = aaria_pin.simulate_run(
        aaria_pin.get_preset("aaria-fig3").table, duration=0.2, rate=50.0, seed=3
    )
    path = aaria_pin.write_run(tmp_path / "run.h5", record)
    again = aaria_pin.read_run(path)
    assert isinstance(again, aaria_pin.RunRecord)
    np.testing.assert_array_equal(again.imu_signals("imu_tool"), record.imu_signals("imu_tool"))
    np.testing.assert_array_equal(again.view("senSen"), record.view("senSen"))
    # the senSen view's IMU columns are the imu array (module 2 of aaria-fig3 is empty: zeros)
    sensen = again.view("senSen")
    np.testing.assert_array_equal(sensen[:, 7:].reshape(-1, 14, 6), again.imu)
    assert not np.any(again.imu_signals("imu_link2_a"))


def test_readme_python_section_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    readme = (Path(__file__).resolve().parent.parent / "README.md").read_text()
    code = readme.split("\n## Python\n", 1)[1].split("```python\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(tmp_path)
    namespace: dict[str, object] = {}
    exec(compile(code, "README.md", "exec"), namespace)
    again = namespace["again"]
    assert isinstance(again, aaria_pin.RunRecord)
    assert again.joint_names[0] == "panda_joint1"
    fig2 = aaria_pin.read_run(tmp_path / "fig2.mat")
    assert fig2.view("senSen").shape == (201, 91)
