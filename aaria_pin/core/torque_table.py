"""The torque table a torque-driven run takes: one row per sample, one column per joint."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = ["check_torques"]


def check_torques(torques: ArrayLike, samples: int, joints: int, what: str = "torques") -> Array:
    """A torque table as a (T, n) float array, or a clear error.

    Args:
        torques: the table, one row per sample, one column per joint [N·m or N]
        samples: T, the samples expected
        joints: n, the joints expected
        what: how the message names the table

    Raises:
        ParameterError: wrong shape (naming the samples and joints expected) or NaN / inf
            (its ``parameter`` is ``"torques"``).
    """
    allowed = f"({samples} samples, {joints} joints)"
    try:
        tau = np.asarray(torques, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(
            f"{what} are not numbers; allowed: a ({samples}, {joints}) table",
            parameter="torques",
            allowed=f"a ({samples}, {joints}) table",
        ) from None
    if tau.shape != (samples, joints):
        raise ParameterError(
            f"{what} have shape {tau.shape}; allowed: {allowed}",
            parameter="torques",
            value=tau.shape,
            allowed=allowed,
        )
    bad = np.argwhere(~np.isfinite(tau))
    if bad.size:
        row, col = bad[0]
        raise ParameterError(
            f"{what}: sample {row}, joint {col + 1} is {tau[row, col]}; allowed: a finite number",
            parameter="torques",
            value=float(tau[row, col]),
            allowed="a finite number",
            element=f"sample {row}, joint {col + 1}",
        )
    return tau
