"""The ``"aaria"`` run kind: run files of ``aaria simulate`` and of data sets (.h5 or .mat).

The arm is rebuilt from the file's inputs (its table, IMU mounts and body dimensions) and posed
by Pinocchio from the stored joint values and the base motion.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from aaria_pin.aaria.dh_robot import build_dh_robot
from aaria_pin.errors import InputFileError
from aaria_pin.viz._run_view import RunFile, RunView, Signals, dh_view, joint_labels, run_file

__all__ = ["is_aaria_run", "load_aaria_run"]


def is_aaria_run(file: Path | RunFile) -> bool:
    """Whether ``file`` is an Aaria run file (not a generic one, which has a layout)."""
    header = run_file(file)
    if header.suffix == ".mat":
        names = header.names
        return "senSen" in names and "attr_format" in names and "attr_layout" not in names
    return header.attributes.get("format") == "aaria_pin run" and "layout" not in header.attributes


def load_aaria_run(file: Path) -> RunView:
    """Read an Aaria run file for drawing.

    Raises:
        InputFileError: an unreadable file, or body dimensions that cannot be used.
    """
    from aaria_pin.aaria.dh_robot import BodyDimensions
    from aaria_pin.aaria.oscillation import base_motion
    from aaria_pin.aaria.sensen import imu_slot_order
    from aaria_pin.files.runfile import read_run

    record = read_run(file)
    dims = None
    if "body_dimensions" in record.attributes:
        try:
            dims = BodyDimensions(**record.attributes["body_dimensions"])
        except TypeError as exc:
            raise InputFileError(f"{file}: body_dimensions cannot be used ({exc})") from None
    robot = build_dh_robot(record.senSenDH, "aaria", dims, imu_mount=record.imu_mount)
    time = np.asarray(record.senSen[:, 0], dtype=float)
    columns = [module - 1 for module in robot.chain.modules]
    kinds = tuple(joint.kind for joint in robot.chain.joints)  # the DH link types
    symbols = ["tau" if kind == "revolute" else "f" for kind in kinds]
    q_labels, tau_labels = joint_labels(symbols, kinds, robot.chain.modules)
    block = record.senSen[:, 7:].reshape(time.size, -1, 6)
    imus = {
        name: np.asarray(block[:, k], dtype=float)
        for k, (name, slot) in enumerate(zip(imu_slot_order(), robot.imu_slots, strict=True))
        if slot.parent is not None
    }
    signals = Signals(
        time,
        np.asarray(record.q[:, columns], dtype=float),
        q_labels,
        np.asarray(record.tau[:, columns], dtype=float),
        tau_labels,
        np.asarray(record.base_wrench, dtype=float),
        imus,
        kinds,
    )
    base = base_motion(record.senSenB, time)
    return dh_view(file.name, "aaria", robot, True, base, signals.q, signals)
