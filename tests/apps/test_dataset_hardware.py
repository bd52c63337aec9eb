"""A data set's hardware drawn per run from its config's ranges (apps/dataset/spec_hardware.py).

Run k's values come from its ``hardware`` stream: inside their ranges, other for another run,
the same for the same seed whatever the workers or an interruption; the file records the
ranges (``hardware``), each run's values (``hardware_values`` by ``hardware_names``), and a run
read back re-makes bit for bit with its own models.
"""

from __future__ import annotations

import re
from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.aaria.hardware import HardwareConfig
from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
from aaria_pin.apps.dataset.generate import DatasetJobStoppedError, generate_dataset
from aaria_pin.apps.dataset.urdf_spec import UrdfDatasetSpec

TABLES = {
    "imu": {"bias_correlation_time": [50.0, 150.0], "gyro": {"noise_density": [1.0e-4, 3.0e-4]}},
}
SETTINGS = {"n_runs": 6, "seed": 11, "duration": 0.2, "rate": 100.0}
NAMES = ["noise_parameters/gyro_noise_density_rad_s_sqrtHz",
         "noise_parameters/bias_correlation_time_s"]  # fmt: skip
"""The drawn values' names: in the order of the run's attributes (its ``noise_parameters``)."""


def _spec(n_runs: int = 6) -> DhDatasetSpec:
    hardware = HardwareConfig.from_mapping(TABLES, "ranges.toml", "config", ranges=True)
    return DhDatasetSpec(**{**SETTINGS, "n_runs": n_runs}, hardware=hardware)


@pytest.fixture(scope="module")
def ranged(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("ranged") / "ranged.h5"
    generate_dataset(path, _spec(), workers=1)
    return path


def test_each_run_draws_its_values_inside_the_ranges(ranged: Path) -> None:
    from aaria_pin.files.dataset.reader import DatasetReader

    with DatasetReader(ranged) as reader:
        assert reader.attributes["hardware_names"] == NAMES
        assert reader.attributes["hardware"] == TABLES
        values = np.array([reader.record(k).tables["hardware_values"] for k in range(6)])
        parameters = [reader.record(k).attributes["noise_parameters"] for k in range(6)]
    assert values.dtype == np.float64 and values.shape == (6, 2)
    assert np.all((values[:, 1] >= 50.0) & (values[:, 1] <= 150.0))
    assert np.all((values[:, 0] >= 1.0e-4) & (values[:, 0] <= 3.0e-4))
    assert len(set(values[:, 0].tolist())) == 6  # every run its own value
    for row, stored in zip(values, parameters, strict=True):  # a run reads back its own model
        assert stored["gyro_noise_density_rad_s_sqrtHz"] == row[0]
        assert stored["bias_correlation_time_s"] == row[1]


def test_the_values_are_a_pure_function_of_the_seed_and_the_run(ranged: Path) -> None:
    from aaria_pin.core.seeds import RunSeeds

    rng = RunSeeds(11, 4).generator("hardware")  # the contract: the run's hardware stream
    # drawn in the tables' order (the IMU's own keys, then [imu.gyro]), stored by name order
    bias_time, density = rng.uniform(50.0, 150.0, None), rng.uniform(1.0e-4, 3.0e-4, None)
    expected = [density, bias_time]
    with h5py.File(ranged, "r") as handle:
        stored = handle["hardware_values"][4]
    np.testing.assert_array_equal(stored, expected)


def test_a_resumed_data_set_equals_an_uninterrupted_one(ranged: Path, tmp_path: Path) -> None:
    def stop_after(done: int, total: int, seconds: float) -> None:
        if done == 2:
            raise KeyboardInterrupt

    path = tmp_path / "resumed.h5"
    with pytest.raises(DatasetJobStoppedError):
        generate_dataset(path, _spec(), workers=2, progress=stop_after)
    generate_dataset(path, _spec(), workers=2, resume=True)
    with h5py.File(ranged, "r") as want, h5py.File(path, "r") as got:
        for name in ("hardware_values", "imu", "checksum", "tau"):
            np.testing.assert_array_equal(got[name][()], want[name][()], err_msg=name)
        assert got.attrs["hardware_names_json"] == want.attrs["hardware_names_json"]


def test_resume_with_other_ranges_is_refused(ranged: Path, tmp_path: Path) -> None:
    import shutil

    from aaria_pin.errors import AariaError

    path = tmp_path / "copy.h5"
    shutil.copy(ranged, path)
    other = HardwareConfig.from_mapping(
        {"imu": {"gyro": {"noise_density": [1.0e-4, 2.0e-4]}}}, ranges=True
    )
    with pytest.raises(AariaError, match="hardware"):
        generate_dataset(path, DhDatasetSpec(**SETTINGS, hardware=other), resume=True)


def test_a_run_read_back_re_makes_bit_for_bit_with_its_drawn_model(ranged: Path) -> None:
    from aaria_pin.apps.remake import remake_record
    from aaria_pin.files.dataset.reader import DatasetReader

    with DatasetReader(ranged) as reader:
        for run in (1, 5):
            stored = reader.record(run)
            again = remake_record(stored)
            assert again.attributes["noise_parameters"] == stored.attributes["noise_parameters"]
            for name in ("q", "tau", "imu", "base_wrench"):
                remade = np.asarray(getattr(again, name), dtype=np.float32)
                np.testing.assert_array_equal(remade, getattr(stored, name), err_msg=name)


def test_a_data_set_without_hardware_tables_is_as_before(tmp_path: Path) -> None:
    path = tmp_path / "plain.h5"
    generate_dataset(path, DhDatasetSpec(**SETTINGS), workers=1)
    with h5py.File(path, "r") as handle:
        assert "hardware_values" not in handle
        assert not any(key.startswith("hardware") for key in handle.attrs)
        assert not {"encoder_json", "torque_sensor_json", "actuator_json"} & set(handle.attrs)


def test_a_urdf_data_set_draws_per_joint_values(tmp_path: Path) -> None:
    from aaria_pin.apps.dataset.spec_sources import DatasetSources

    config = tmp_path / "ranges.toml"
    config.write_text("[imu.accel]\nnoise_density = [1.0e-4, 2.0e-4]\n")
    spec = DatasetSources(
        n_runs=2, duration=0.2, robot="ur5", config_file=config, imu_model="adis16485"
    ).spec()
    assert isinstance(spec, UrdfDatasetSpec)
    assert spec.hardware_names() == ("noise_parameters/accel_noise_density_m_s2_sqrtHz",)
    first, second = spec.run_hardware(0), spec.run_hardware(1)
    assert first.imu.accel.noise_density != second.imu.accel.noise_density
    assert spec.run_settings(1).noise_model == second.imu


def test_the_card_lists_every_hardware_term_with_its_range_and_unit(tmp_path: Path) -> None:
    from aaria_pin.apps.dataset.card_file import dataset_card
    from aaria_pin.apps.dataset.card_text import card_text

    tables = {**TABLES, "encoder": {"noise": [0.0, 1.0e-3]}, "actuator": {"viscous": 0.5}}
    hardware = HardwareConfig.from_mapping(tables, "ranges.toml", "config", ranges=True)
    path = tmp_path / "card.h5"
    generate_dataset(path, DhDatasetSpec(**{**SETTINGS, "n_runs": 2}, hardware=hardware))
    card = dataset_card(path)
    assert card.hardware == tables and card.joint_hardware["actuator"]["viscous"] == 0.5
    assert "torque_sensor" not in card.joint_hardware
    text = card_text(card)
    assert "gyro_noise_density_rad_s_sqrtHz = 0.0002 (drawn per run from [0.0001, 0.0003]" in text
    assert "bias_correlation_time_s = 100 (drawn per run from [50, 150]" in text
    assert "  viscous = 0.5 [N·m·s/rad or N·s/m]\n" in text
    assert "tables: tau_motor [N*m or N (T x n)], tau_armature" in text
    assert "torque_sensor: off (no tau_measured, torque_sensor_bias, torque_sensor_scale)" in text
    assert "noise = [0.0005, 0.0005, 0.0005, 0.0005, 0.0005, 0.0005] [rad or m] (drawn" in text


def test_a_range_around_zero_and_whole_counts(tmp_path: Path) -> None:
    """A time offset in [-5, 5] ms is on in every run (its middle, 0, is off): the layout holds
    its table; encoder counts drawn from a range are whole; the encoder's series window."""
    from aaria_pin.files.dataset.reader import DatasetReader

    encoder = {"counts_per_revolution": [1000.0, 5000.0], "counts_per_metre": 1e5}
    tables = {"imu": {"time_offset": [-0.005, 0.005]}, "encoder": encoder}
    hardware = HardwareConfig.from_mapping(tables, "ranges.toml", "config", ranges=True)
    path = tmp_path / "zero.h5"
    generate_dataset(path, DhDatasetSpec(**{**SETTINGS, "n_runs": 3}, hardware=hardware), workers=1)
    with DatasetReader(path) as reader:
        assert reader.complete.all()
        offsets = [
            float(reader.record(k).tables["imu_error_time_offset"].ravel()[0]) for k in range(3)
        ]
        counts = np.array([reader.record(k).attributes["encoder"]["counts_per_revolution"]
                           for k in range(3)])  # fmt: skip
        assert "q_measured" in reader.series_names
        _, _, window = next(iter(reader.windows(5, names=("q", "q_measured"))))
    assert all(-0.005 <= o <= 0.005 and o != 0.0 for o in offsets)
    assert np.array_equal(counts, np.rint(counts)) and ((counts >= 1000) & (counts <= 5000)).all()
    assert window["q"].shape == window["q_measured"].shape == (5, 6)


@pytest.mark.parametrize(
    ("tables", "said"),
    [({"imu": {"decimation": [1, 4]}}, "imu.decimation is [1, 4]; allowed: a whole number"),
     ({"encoder": {"noise": [1e-4, 2e-4, 3e-4]}}, "encoder.noise has 3 values; allowed: one")],
)  # fmt: skip
def test_refused_before_any_run(tmp_path: Path, tables: dict[str, object], said: str) -> None:
    """A range of a filter setting, a per-joint list of another length: one line, no file."""
    from aaria_pin.errors import ParameterError

    path = tmp_path / "refused.h5"
    with pytest.raises(ParameterError, match=re.escape(said)) as caught:
        hardware = HardwareConfig.from_mapping(tables, "ranges.toml", "config", ranges=True)
        generate_dataset(path, DhDatasetSpec(**SETTINGS, hardware=hardware), workers=1)
    assert caught.value.parameter == "config" and not path.exists()
