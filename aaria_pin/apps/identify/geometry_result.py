"""What the kinematic identification found: the table, the IMU mounts, their uncertainty."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from aaria_pin.apps.identify._json import json_number
from aaria_pin.core.record import ImuMount
from aaria_pin.core.se3 import Array

__all__ = ["Deficiency", "KinematicIdentification", "TruthErrors"]


@dataclass(frozen=True)
class Deficiency:
    """A combination of parameters the data cannot determine (a null direction of the fit).

    Attributes:
        parameters: the DH parameters in it
        coefficients: their coefficients in the null direction (the first is 1)
        description: the combination in words
    """

    parameters: tuple[str, ...]
    coefficients: tuple[float, ...]
    description: str


@dataclass(frozen=True)
class TruthErrors:
    """Errors of an identification against the truth a simulated record holds.

    Attributes:
        link_types_true: the true link type per module (0, 1, 2)
        link_types_right: whether each module's estimated link type is the true one
        tool_tip_rms: RMS of the tool tip's position error over the run, base frame [m]
        tool_tip_max: its largest value [m]
        axis_angle_max: per module present in both, the largest angle between the estimated
            and the true joint axis over the run [rad]
        coverage: per parameter kind (``alpha``, ``a``, ``d``, ``theta``, ``a7``), how many
            of the determined DH parameters are within 2σ of the true table's entry, and how
            many there are
    """

    link_types_true: tuple[int, ...]
    link_types_right: tuple[bool, ...]
    tool_tip_rms: float
    tool_tip_max: float
    axis_angle_max: dict[int, float]
    coverage: dict[str, tuple[int, int]] = field(default_factory=dict)


@dataclass(frozen=True)
class KinematicIdentification:
    """The identified kinematic model of an Aaria arm.

    Attributes:
        table: the estimated 8 × 5 extended DH table ``[alpha, a, theta, d, link type]``
        link_types: the estimated link type of each module (0 empty, 1 revolute, 2 prismatic)
        mounts: every IMU's estimated mount, in record order (base and tool: identity, as
            defined; empty slots: zero pose, parent ``""``)
        parameter_names: the fitted parameters (``alpha2``, ``d2``, ``a2``, ``a7``,
            ``imu_link2_a.rx`` … ``.z``: rotation vector [rad] and position [m] in the link's
            post-joint frame)
        estimates: their values [rad, m]
        sigmas: their standard deviations from the fit (NaN: not determined by the data)
        residual_rms: per predicted IMU, the RMS of the gyroscope [rad/s] and accelerometer
            [m/s²] residuals over the whole run
        deficiencies: the parameter combinations the data cannot determine
        truth: errors against the truth the record holds, or None
        fit: how the fit went (samples used, iterations, seconds, start's RMS; ``starts``:
            the starts fitted on every sample, ``start``: the result's (``start table``,
            ``closed form``, ``other``), ``closed_form``: whether the closed-form start was
            built, ``link_types_from_start``: the modules whose kind a start table decided)
    """

    table: Array
    link_types: tuple[int, ...]
    mounts: tuple[ImuMount, ...]
    parameter_names: tuple[str, ...]
    estimates: Array
    sigmas: Array
    residual_rms: dict[str, dict[str, float]]
    deficiencies: tuple[Deficiency, ...]
    truth: TruthErrors | None
    fit: dict[str, Any]

    def to_json(self) -> dict[str, Any]:
        """A JSON-ready dict of everything (arrays as lists, NaN as None)."""
        out: dict[str, Any] = {
            "table": self.table.tolist(),
            "link_types": list(self.link_types),
            "parameters": [
                {"name": name, "estimate": float(value), "sigma": json_number(sigma)}
                for name, value, sigma in zip(
                    self.parameter_names, self.estimates, self.sigmas, strict=True
                )
            ],
            "mounts": [
                {
                    "name": m.name,
                    "parent": m.parent,
                    "T_parent_imu": np.asarray(m.T_parent_imu).tolist(),
                }
                for m in self.mounts
            ],
            "residual_rms": self.residual_rms,
            "deficiencies": [
                {
                    "parameters": list(d.parameters),
                    "coefficients": list(d.coefficients),
                    "description": d.description,
                }
                for d in self.deficiencies
            ],
            "fit": self.fit,
            "truth": None,
        }
        if self.truth is not None:
            t = self.truth
            out["truth"] = {
                "link_types_true": list(t.link_types_true),
                "link_types_right": list(t.link_types_right),
                "tool_tip_rms_m": json_number(t.tool_tip_rms),
                "tool_tip_max_m": json_number(t.tool_tip_max),
                "axis_angle_max_rad": {str(k): v for k, v in t.axis_angle_max.items()},
                "sigma_coverage": {k: list(v) for k, v in t.coverage.items()},
            }
        return out

    @property
    def failure(self) -> str | None:
        """Why the fit is not a result, one line (``fit["failure"]``), or None."""
        failure = self.fit.get("failure")
        return failure if isinstance(failure, str) else None

    def summary(self) -> list[str]:
        """The identification as a few lines of text: structure, table, residuals, truth.

        A failed fit (:attr:`failure`) is one line, ``identification failed: ...``: its table
        is not a result.
        """
        if self.failure is not None:
            return [f"identification failed: {self.failure}"]
        names = {0: "empty", 1: "revolute", 2: "prismatic"}
        lines = [
            "structure: " + ", ".join(f"{m + 1} {names[t]}" for m, t in enumerate(self.link_types)),
            "table [alpha a theta d type]:",
        ]
        lines += [
            "  " + " ".join(f"{v:9.5f}" for v in row[:4]) + f" {int(row[4])}" for row in self.table
        ]
        n_dh = 1 + max(i for i, n in enumerate(self.parameter_names) if "." not in n)
        lines.append(
            "sigma: "
            + ", ".join(
                f"{name} {value:.5g} ± {'undetermined' if np.isnan(sigma) else f'{sigma:.2g}'}"
                for name, value, sigma in zip(
                    self.parameter_names[:n_dh], self.estimates, self.sigmas, strict=False
                )
            )
        )
        lines += [f"not determined: {d.description}" for d in self.deficiencies]
        lines += [
            f"residual RMS {name}: gyroscope {rms['gyro_rad_s']:.3g} rad/s, accelerometer "
            f"{rms['accel_m_s2']:.3g} m/s^2"
            for name, rms in self.residual_rms.items()
        ]
        lines.append(f"fit {self.fit['seconds']:.1f} s on {self.fit['samples']} samples")
        truth = self.truth
        if truth is not None:
            lines.append(
                f"against the truth: link types {sum(truth.link_types_right)}/6 right, tool tip "
                f"RMS {truth.tool_tip_rms:.3g} m, max {truth.tool_tip_max:.3g} m, joint axes "
                f"within {max(truth.axis_angle_max.values(), default=0.0):.3g} rad"
            )
        return lines
