"""The checks of a read run: its kind's tables, its attributes' types, finite data."""

from __future__ import annotations

import numpy as np
import pytest

from aaria_pin.core.record import ImuMount, RunRecord
from aaria_pin.core.record_checks import (
    KIND_TABLES,
    check_attributes,
    check_finite,
    check_kind_layout,
    check_record,
    record_source,
)
from aaria_pin.errors import InputFileError


def _record(
    kind: str | None = "dh", samples: int = 20, joints: int = 3, imus: int = 2
) -> RunRecord:
    """A small record of zeros with the tables of a DH run."""
    zeros = np.zeros((samples, joints))
    return RunRecord(
        time=np.arange(samples) / 100.0,
        joint_names=tuple(f"j{k}" for k in range(joints)),
        q=zeros,
        qd=zeros.copy(),
        qdd=zeros.copy(),
        tau=zeros.copy(),
        base_pose=np.tile(np.eye(4), (samples, 1, 1)),
        base_wrench=np.zeros((samples, 6)),
        tool_pose=np.tile(np.eye(4), (samples, 1, 1)),
        imu=np.zeros((samples, imus, 6)),
        imu_mounts=tuple(ImuMount(f"imu{s}", "base", np.eye(4)) for s in range(imus)),
        tables={name: np.ones((2, 4)) for name in ("senSenDH", "senSenJ", "senSenB")},
        attributes={"rate": 100.0, "duration": 0.2, **({} if kind is None else {"kind": kind})},
    )


def test_a_whole_run_passes_and_the_source_names_the_run_of_a_data_set() -> None:
    check_record(_record(), "run.h5")
    check_record(_record(kind=None), "run.h5")  # an older file: no kind, no check of tables
    assert record_source("run.h5") == "run.h5"
    assert record_source("ds.h5", run=3) == "run 3 of ds.h5"


@pytest.mark.parametrize(
    ("name", "index", "value", "where"),
    [
        ("tau", (17, 2), np.nan, "tau has NaN at sample 17, joint 2"),
        ("q", (0, 0), np.inf, "q has inf at sample 0, joint 0"),
        ("imu", (5, 1, 4), -np.inf, "imu has -inf at sample 5, IMU 1, signal 4"),
        ("base_pose", (3, 2, 1), np.nan, "base_pose has NaN at sample 3, row 2, column 1"),
        ("time", (19,), np.nan, "time has NaN at sample 19"),
    ],
)
def test_the_first_bad_value_is_named_with_its_array_and_index(
    name: str, index: tuple[int, ...], value: float, where: str
) -> None:
    record = _record()
    array = getattr(record, name)
    array[index] = value
    if index[0] < array.shape[0] - 1:
        array[-1] = np.nan  # a later bad value is not the one named
    with pytest.raises(InputFileError) as error:
        check_record(record, record_source("ds.h5", run=4))
    assert str(error.value) == f"run 4 of ds.h5: {where}; allowed: finite values"
    assert error.value.parameter == "file" and "\n" not in str(error.value)


def test_a_table_and_the_mounts_are_checked_too_and_only_the_inputs_without_series() -> None:
    record = _record()
    record.tables["senSenJ"][1, 3] = np.nan
    with pytest.raises(InputFileError, match=r"senSenJ has NaN at row 1, column 3"):
        check_finite(record.arrays(), "run.h5")
    record = _record()
    record.tau[0, 0] = np.nan
    check_record(record, "run.h5", series=False)  # the series were not read
    record.tables["senSenB"][0, 0] = np.inf
    with pytest.raises(InputFileError, match=r"senSenB has inf at row 0, column 0"):
        check_record(record, "run.h5", series=False)  # the inputs were
    mounts = np.zeros((2, 4, 4))
    mounts[1, 0, 3] = np.inf
    with pytest.raises(InputFileError, match=r"imu_mount has inf at IMU 1, row 0, column 3"):
        check_finite({"imu_mount": mounts}, "run.h5")
    check_finite({"names": np.array(["a", "b"])}, "run.h5")  # not numbers: not this check's


def test_an_unknown_kind_and_a_missing_table_are_one_line() -> None:
    with pytest.raises(InputFileError) as error:
        check_kind_layout(_record(kind="bogus"), "run.h5")
    assert str(error.value) == (
        "run.h5: attribute 'kind' is 'bogus'; allowed: dh, urdf, wrist, pick-place"
    )
    record = _record()
    del record.tables["senSenDH"]
    with pytest.raises(InputFileError) as error:
        check_kind_layout(record, "run.h5")
    assert str(error.value) == (
        "run.h5: array senSenDH is missing; allowed: a dh run file has senSenDH, senSenJ, senSenB"
    )
    urdf = _record(kind="urdf")
    with pytest.raises(InputFileError, match="array joint_table is missing; allowed: a urdf run"):
        check_kind_layout(urdf, "run.h5")
    assert set(KIND_TABLES) == {"dh", "urdf", "wrist", "pick-place"}
    check_kind_layout(_record(kind="wrist"), "run.h5")


@pytest.mark.parametrize(
    ("attributes", "message"),
    [
        ({"rate": "100"}, "attribute 'rate' is '100'; allowed: a positive number"),
        ({"duration": [1.0, 2.0]}, "attribute 'duration' is \\[1.0, 2.0\\]; allowed: a positive"),
        ({"rate": -3.0}, "attribute 'rate' is -3.0; allowed: a positive number of Hz"),
        ({"rate": True}, "attribute 'rate' is True; allowed: a positive number"),
        ({"kind": 3}, "attribute 'kind' is 3; allowed: text"),
        ({"robot": ["a", "b"]}, "attribute 'robot' is \\['a', 'b'\\]; allowed: text"),
        ({"noise": "yes"}, "attribute 'noise' is 'yes'; allowed: true or false"),
        ({"seed": "abc"}, "run.h5: .*abc"),
    ],
)
def test_attributes_of_the_wrong_type_are_refused(attributes: dict, message: str) -> None:
    with pytest.raises(InputFileError, match=message) as error:
        check_attributes({"rate": 100.0, "duration": 1.0, **attributes}, "run.h5")
    assert str(error.value).startswith("run.h5: ") and error.value.parameter == "file"


def test_matlab_numbers_for_a_bool_and_a_seed_are_accepted() -> None:
    """MATLAB re-saves a bool as 0/1 and an integer as a double: read as the same settings."""
    from aaria_pin.core.run_metadata import RunMetadata

    matlab = {"noise": 1, "seed": 4.0, "rate": 100, "duration": 1}
    assert check_attributes(matlab, "run.mat") is None  # accepted, not refused
    meta = RunMetadata.from_attributes(matlab)
    assert (meta.noise, meta.seed, meta.rate, meta.duration) == (True, 4, 100.0, 1.0)
    assert check_attributes({}, "run.h5") is None  # every shared attribute has a default
    with pytest.raises(InputFileError):
        check_attributes({"noise": 2}, "run.mat")  # 0 and 1 only


@pytest.mark.parametrize(("value", "what"), [(-1.0, "decreases"), (0.04, "repeats")])
def test_times_that_do_not_strictly_increase_are_refused(value: float, what: str) -> None:
    record = _record()
    record.time[5] = value
    with pytest.raises(InputFileError) as error:
        check_record(record, "run.h5")
    assert str(error.value) == (
        f"run.h5: time {what} at sample 5; allowed: strictly increasing times"
    )
    assert error.value.parameter == "file"
    check_record(record, "run.h5", series=False)  # the series were not read
    one = _record(samples=1)
    check_record(one, "run.h5")  # a single sample has no order to check


def _with_tables(**tables: np.ndarray) -> RunRecord:
    from dataclasses import replace

    record = _record()
    return replace(record, tables={**record.tables, **tables})


def test_the_joint_hardware_tables_are_optional_and_checked_when_there() -> None:
    good = _with_tables(
        q_measured=np.zeros((20, 3)), tau_motor=np.zeros((20, 3)), encoder_offset=np.zeros((1, 3))
    )
    check_record(good, "run.h5")
    for name, table, allowed in [
        ("q_measured", np.zeros((19, 3)), "(20, 3) (T × n)"),
        ("tau_friction", np.zeros((20, 2)), "(20, 3) (T × n)"),
        ("torque_sensor_bias", np.zeros(3), "(1, 3) (1 × n, one per joint)"),
    ]:
        with pytest.raises(InputFileError) as caught:
            check_record(_with_tables(**{name: table}), "run.h5")
        assert str(caught.value) == (
            f"run.h5: array {name} has shape {table.shape}; allowed: {allowed}"
        )
        assert caught.value.parameter == "file"


def test_a_nan_in_a_joint_hardware_table_names_its_sample_and_joint() -> None:
    measured = np.zeros((20, 3))
    measured[7, 2] = np.nan
    with pytest.raises(InputFileError, match=r"q_measured has NaN at sample 7, joint 2;"):
        check_record(_with_tables(q_measured=measured), "run.h5")
    offset = np.zeros((1, 3))
    offset[0, 1] = np.inf
    with pytest.raises(InputFileError, match=r"encoder_offset has inf at row 0, joint 1;"):
        check_record(_with_tables(encoder_offset=offset), "run.h5")
