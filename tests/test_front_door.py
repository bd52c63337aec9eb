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


FRONT_DOOR = {
    # the engine: one simulate, its settings and seeds, the motions, the robots
    "simulate",
    "simulate_pieces",
    "RunSettings",
    "RunSeeds",
    "SineTable",
    "FourierMotion",
    "SampledTrajectory",
    "TorqueDrive",
    "preset_arm",
    "dh_arm",
    "urdf_robot_run",
    # data sets: the generator and its spec
    "generate_dataset",
    "DatasetSources",
    "DatasetSpec",
    "DatasetJob",
    # the wrist's kinematics, the rotation conversions, reading and writing
    "wrist_fk",
    "wrist_ik",
    "matrix_from_angles",
    "angles_from_matrix",
    "open_record",
    "read_run",
    "write_run",
}


def test_the_front_door_exports_what_a_python_user_needs() -> None:
    assert FRONT_DOOR <= set(aaria_pin.__all__)
    assert set(aaria_pin.__all__) <= set(dir(aaria_pin)) | set(aaria_pin._LAZY)
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        aaria_pin.nope  # noqa: B018


def test_the_packages_front_doors_are_lazy_too() -> None:
    code = (
        "import sys, aaria_pin.apps.dataset, aaria_pin.apps.wrist; "
        "print(sorted(m for m in ('pinocchio', 'h5py', 'scipy', 'numba', 'numpy')"
        " if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
    from aaria_pin.apps import dataset, wrist

    assert (
        dataset.generate_dataset
        is importlib.import_module(dataset._LAZY["generate_dataset"]).generate_dataset
    )
    assert wrist.wrist_ik is importlib.import_module(wrist._LAZY["wrist_ik"]).wrist_ik


def _rz(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _ry(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _rx(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def test_the_wrist_and_the_rotations_against_products_of_elementary_rotations() -> None:
    q = np.array([0.3, 0.8, -1.2])
    T_base_tool = aaria_pin.wrist_fk(q)
    # the wrist is a ZYZ Euler wrist: R = Rz(θ1) Ry(θ2) Rz(θ3), the tool on its z axis
    R = _rz(q[0]) @ _ry(q[1]) @ _rz(q[2])
    np.testing.assert_allclose(T_base_tool[:3, :3], R, atol=1e-15)
    np.testing.assert_allclose(np.cross(T_base_tool[:3, 3], R[:, 2]), 0.0, atol=1e-15)
    ik = aaria_pin.wrist_ik(R)
    np.testing.assert_allclose(ik.solutions[0], q, atol=1e-12)
    np.testing.assert_allclose(ik.solutions[1], [q[0] - np.pi, -q[1], q[2] + np.pi], atol=1e-12)
    # moving axes ZYX: Rz Ry Rx; fixed axes xyz: the same product, angles reversed
    a = np.array([0.1, 0.2, 0.3])
    moving = _rz(a[0]) @ _ry(a[1]) @ _rx(a[2])
    np.testing.assert_allclose(aaria_pin.matrix_from_angles(a, "ZYX"), moving, atol=1e-15)
    np.testing.assert_allclose(aaria_pin.matrix_from_angles(a[::-1], "xyz"), moving, atol=1e-15)
    np.testing.assert_allclose(aaria_pin.angles_from_matrix(moving, "ZYX").angles, a, atol=1e-15)
    locked = aaria_pin.angles_from_matrix(_rz(0.4) @ _rz(0.1), "ZYZ")  # θ2 = 0: gimbal lock
    np.testing.assert_allclose(locked.angles, [0.5, 0.0, 0.0], atol=1e-15)
    assert locked.locked


def test_a_run_and_a_data_set_run_through_the_front_door(tmp_path: Path) -> None:
    settings = aaria_pin.RunSettings(duration=0.2, rate=50.0)
    record = aaria_pin.simulate(aaria_pin.preset_arm("aaria-fig3"), settings=settings, seeds=3)
    again = aaria_pin.open_record(aaria_pin.write_run(tmp_path / "run.h5", record))
    assert isinstance(again, aaria_pin.RunRecord)
    np.testing.assert_array_equal(again.time, np.arange(11) / 50.0)
    np.testing.assert_array_equal(again.imu_signals("imu_tool"), record.imu_signals("imu_tool"))
    # the senSen view's IMU columns are the imu array (module 2 of aaria-fig3 is empty: zeros)
    sensen = again.view("senSen")
    np.testing.assert_array_equal(sensen[:, 7:].reshape(-1, 14, 6), again.imu)
    assert not np.any(again.imu_signals("imu_link2_a"))

    sources = aaria_pin.DatasetSources(
        n_runs=2, seed=5, duration=0.2, rate=50.0, preset="aaria-fig2"
    )
    spec = sources.spec()
    assert isinstance(spec, aaria_pin.DatasetSpec)
    path = tmp_path / "ds.h5"
    report = aaria_pin.generate_dataset(path, spec, aaria_pin.DatasetJob(workers=1))
    assert report.complete == 2
    run = aaria_pin.open_record(path, run=1)
    assert run.imu.shape == (11, 14, 6) and run.metadata.rate == 50.0
    with pytest.raises(aaria_pin.ParameterError) as error:
        aaria_pin.open_record(path)  # a data set needs its run
    assert error.value.parameter == "run"


def test_readme_python_section_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    readme = (Path(__file__).resolve().parent.parent / "README.md").read_text()
    code = readme.split("\n## Python\n", 1)[1].split("```python\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(tmp_path)
    namespace: dict[str, object] = {}
    exec(compile(code, "README.md", "exec", dont_inherit=True), namespace)
    again = namespace["again"]
    assert isinstance(again, aaria_pin.RunRecord)
    assert again.joint_names[0] == "panda_joint1" and again.tau.shape == (201, 9)
    fig2 = aaria_pin.read_run(tmp_path / "fig2.mat")
    assert fig2.view("senSen").shape == (201, 91)
    excited = namespace["excited"]
    assert isinstance(excited, aaria_pin.RunRecord) and excited.metadata.motion == "fourier"
    np.testing.assert_array_equal(excited.time, fig2.time)
