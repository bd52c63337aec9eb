"""A driven run's numbers do not depend on whether its kernels were compiled or loaded.

Found by review: compiled with ``fastmath``, the drive's kernels gave a run made right after a
first compile and its ``--from`` re-make from numba's disk cache that differed in the last bits
(1.7e-12 in ``qdd``), so a file could not be re-made bit for bit. Now they are ``exact``: a
closed-loop run and a torque-driven run made by a process that compiles the kernels into an
empty cache are re-made bit for bit by a process that loads them from it.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from aaria_pin.files.runfile import read_run


def _aaria(env: dict[str, str], cwd: Path, *args: str) -> None:
    subprocess.run(
        [sys.executable, "-m", "aaria_pin.cli", *args], env=env, cwd=cwd, check=True,
        capture_output=True, text=True,
    )  # fmt: skip


def test_a_run_compiled_fresh_is_re_made_from_the_cache(tmp_path: Path) -> None:
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    env["NUMBA_CACHE_DIR"] = str(tmp_path / "numba-cache")
    common = ("--robot", "ur5", "--duration", "0.3", "--no-noise")
    _aaria(env, tmp_path, "simulate", *common, "-o", "tau.h5")
    _aaria(env, tmp_path, "simulate", *common, "--drive", "pd", "-o", "pd.h5")  # compiles
    _aaria(env, tmp_path, "simulate", *common, "--drive", "torque", "--torques", "tau.h5",
           "--limits", "ignore", "-o", "torque.h5")  # fmt: skip
    for name in ("pd", "torque"):  # loads from the cache
        _aaria(env, tmp_path, "simulate", "--from", f"{name}.h5", "-o", f"{name}-again.h5")
        made, again = read_run(tmp_path / f"{name}.h5"), read_run(tmp_path / f"{name}-again.h5")
        for array in ("q", "qd", "qdd", "tau", "imu"):
            np.testing.assert_array_equal(getattr(again, array), getattr(made, array), array)
