"""The ``"wrist"`` run kind: run files of ``aaria wrist simulate`` (.h5 or .mat).

The report's spherical wrist, three revolute joints on a fixed base, no IMUs.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from aaria_pin.core.trajectory import BaseMotion
from aaria_pin.errors import InputFileError
from aaria_pin.viz._run_view import RunFile, RunView, Signals, dh_view, joint_labels, run_file

__all__ = ["is_wrist_run", "load_wrist_run"]


def is_wrist_run(file: Path | RunFile) -> bool:
    """Whether ``file`` holds ``time``, ``q``, ``tau`` and ``targets_rad`` (a wrist run)."""
    header = run_file(file)
    return {"time", "q", "tau", "targets_rad"} <= header.names | set(header.attributes)


def load_wrist_run(file: Path) -> RunView:
    """Read a wrist run file for drawing.

    Raises:
        InputFileError: ``q`` or ``tau`` not of shape T × 3.
    """
    from aaria_pin.apps.wrist.run import report_wrist

    if file.suffix.lower() == ".mat":
        from scipy.io import loadmat

        contents = loadmat(file)
        arrays = {name: np.asarray(contents[name], dtype=float) for name in ("time", "q", "tau")}
    else:
        import h5py

        with h5py.File(file, "r") as handle:
            arrays = {name: np.asarray(handle[name], dtype=float) for name in ("time", "q", "tau")}
    time = arrays["time"].reshape(-1)
    q, tau = (arrays[name].reshape(time.size, -1) for name in ("q", "tau"))
    robot = report_wrist()
    if q.shape[1] != len(robot.chain.joints) or tau.shape != q.shape:
        raise InputFileError(f"{file}: q of shape {q.shape}, tau {tau.shape}; allowed: T × 3 each")
    modules = robot.chain.modules
    kinds = ("revolute",) * len(modules)
    q_labels, tau_labels = joint_labels(["tau"] * len(modules), kinds, modules)
    signals = Signals(time, q, q_labels, tau, tau_labels, joint_kinds=kinds)
    return dh_view(file.name, "wrist", robot, False, BaseMotion.resting(time.size), q, signals)
