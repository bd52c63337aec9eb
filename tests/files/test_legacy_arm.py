"""The 0.1.0 DH arm registry the files layer's legacy readers use (the Aaria layer registers it)."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from aaria_pin.errors import InputFileError
from aaria_pin.files import legacy_arm as registry
from aaria_pin.files.legacy_arm import LegacyArm, base_pose_from_table, legacy_arm
from aaria_pin.files.runfile import read_run

FIXTURES = Path(__file__).resolve().parents[1] / "fixtures" / "v0_1_0"


def test_import_aaria_pin_registers_the_aaria_arm() -> None:
    arm = legacy_arm(FIXTURES / "dh_run.h5")
    assert arm.robot == "aaria-arm" and arm.modules == 6 and arm.slots == 14
    assert arm.joints == tuple(f"joint{k}" for k in range(1, 7))


def test_a_toy_arm_registered_names_the_records_joints_and_parents(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    toy = LegacyArm(
        robot="toy",
        joints=tuple(f"j{k}" for k in range(6)),
        slots=14,
        slot_parent=lambda slot: "mount_" + slot,
    )
    monkeypatch.setattr(registry, "_REGISTERED", [toy])
    record = read_run(FIXTURES / "dh_run.h5")
    assert record.joint_names == toy.joints and record.attributes["robot"] == "toy"
    with h5py.File(FIXTURES / "dh_run.h5", "r") as handle:
        stored = handle["imu_mount"][()]
    empty = [not np.any(pose) for pose in stored]
    assert any(empty) and not all(empty)  # the fixture has an empty module
    assert [m.parent for m in record.imu_mounts] == [
        "" if zero else "mount_" + m.name for m, zero in zip(record.imu_mounts, empty, strict=True)
    ]


def test_without_a_registered_arm_a_dh_file_is_refused_naming_file(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(registry, "_REGISTERED", [])
    with pytest.raises(InputFileError, match="no layer registered") as bad:
        read_run(FIXTURES / "dh_run.h5")
    assert bad.value.parameter == "file"


def test_a_fixed_base_is_the_identity() -> None:
    time = np.linspace(0.0, 1.0, 5)
    fixed = base_pose_from_table(None, time)
    np.testing.assert_array_equal(fixed, np.broadcast_to(np.eye(4), (5, 4, 4)))
