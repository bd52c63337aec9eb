"""The result of a rigid-pair fit: B's pose and time offset relative to A, σ, text and JSON.

Made by :func:`~aaria_pin.apps.identify.rigid.identify_rigid`; :meth:`RigidPairFit.lines` is
the report of ``aaria identify --rigid``, :meth:`RigidPairFit.to_json` its ``--json``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from aaria_pin.core.se3 import Array

__all__ = ["RigidPairFit"]


@dataclass(frozen=True)
class RigidPairFit:
    """B's pose and time offset relative to A, with σ, and what the data did not determine.

    Attributes:
        imu_a: A's name
        imu_b: B's name
        rotation: (3, 3) ``R_AB`` (``v_A = R_AB·v_B``)
        rotation_sigma: (3,) σ of the rotation about A's axes [rad]
        position: (3,) B's origin in A's frame [m]
        position_sigma: (3,) [m]
        time_offset: B's stamp ``t`` is A's instant ``t + time_offset`` [s]
        time_offset_sigma: [s]
        gyro_bias_a: (3,) A's gyroscope bias, mean over the run [rad/s]
        gyro_bias_b: (3,) B's [rad/s]
        accel_bias_b: (3,) B's accelerometer bias less A's (in B's axes) [m/s²]
        noise: A gyro, A accel, B gyro, B accel: the residuals' RMS [rad/s, m/s²]
        samples: A's and B's samples in the fit
        iterations: Gauss–Newton steps
        converged: the last step changed the cost by < 1e-9 of it
        undetermined: what the data do not determine, one sentence each
        covariance: (7, 7) of rotation [rad], position [m], offset [s]
        failure: one sentence when the fit ended above the noise floor
            (:data:`~aaria_pin.apps.identify.rigid.ABOVE_FLOOR`), else empty: the numbers are
            then not a result
        knot_interval: the knot spacing of the body's splines [s] (0: not given)
    """

    imu_a: str
    imu_b: str
    rotation: Array
    rotation_sigma: Array
    position: Array
    position_sigma: Array
    time_offset: float
    time_offset_sigma: float
    gyro_bias_a: Array
    gyro_bias_b: Array
    accel_bias_b: Array
    noise: Array
    samples: tuple[int, int]
    iterations: int
    converged: bool
    undetermined: tuple[str, ...] = ()
    covariance: Array = field(default_factory=lambda: np.zeros((7, 7)), repr=False)
    failure: str = ""
    knot_interval: float = 0.0

    def rotation_error(self, truth: Array) -> float:
        """The angle between the estimated and a true ``R_AB`` [rad]."""
        cos = (np.trace(np.asarray(truth).T @ self.rotation) - 1.0) / 2.0
        return float(np.arccos(np.clip(cos, -1.0, 1.0)))

    def lines(self) -> list[str]:
        """The result as text lines (the ``aaria identify --rigid`` report)."""
        from scipy.spatial.transform import Rotation

        rpy = np.degrees(Rotation.from_matrix(self.rotation).as_euler("xyz"))
        position = "  ".join(
            f"{x:.3f} +/- {s:.3f}"
            for x, s in zip(self.position * 1e3, self.position_sigma * 1e3, strict=True)
        )
        turn_sigma = ", ".join(f"{s:.4f}" for s in np.degrees(self.rotation_sigma))
        gyro_a, accel_a, gyro_b, accel_b = self.noise
        state = "" if self.converged else " (not converged)"
        knots = f", knots every {self.knot_interval:.3g} s" if self.knot_interval > 0.0 else ""
        lines = [
            f"rigid pair {self.imu_a} -> {self.imu_b}: {self.samples[0]} + {self.samples[1]} "
            f"samples, {self.iterations} iterations{state}{knots}",
            f"  position of {self.imu_b} in {self.imu_a} [mm]: {position}",
            "  rotation (roll pitch yaw, xyz) [deg]: "
            + "  ".join(f"{x:.4f}" for x in rpy)
            + f"  (sigma about {self.imu_a}'s axes: {turn_sigma})",
            f"  time offset of {self.imu_b} [ms]: {self.time_offset * 1e3:.4f} "
            f"+/- {self.time_offset_sigma * 1e3:.4f}",
            f"  residual RMS: gyro {gyro_a:.3g} / {gyro_b:.3g} rad/s, "
            f"accel {accel_a:.3g} / {accel_b:.3g} m/s^2 ({self.imu_a} / {self.imu_b})",
        ]
        lines += [f"  not determined: {text}" for text in self.undetermined]
        return lines + ([f"  fit failed: {self.failure}"] if self.failure else [])

    def to_json(self) -> dict[str, object]:
        """The result as JSON-ready values (SI units in the keys)."""
        return {
            "imu_a": self.imu_a,
            "imu_b": self.imu_b,
            "rotation": self.rotation.tolist(),
            "rotation_sigma_rad": self.rotation_sigma.tolist(),
            "position_m": self.position.tolist(),
            "position_sigma_m": self.position_sigma.tolist(),
            "time_offset_s": self.time_offset,
            "time_offset_sigma_s": self.time_offset_sigma,
            "gyro_bias_a_rad_s": self.gyro_bias_a.tolist(),
            "gyro_bias_b_rad_s": self.gyro_bias_b.tolist(),
            "accel_bias_b_m_s2": self.accel_bias_b.tolist(),
            "residual_rms": dict(
                zip(
                    ("gyro_a_rad_s", "accel_a_m_s2", "gyro_b_rad_s", "accel_b_m_s2"),
                    self.noise.tolist(),
                    strict=True,
                )
            ),
            "samples": list(self.samples),
            "iterations": self.iterations,
            "converged": self.converged,
            "undetermined": list(self.undetermined),
            "failure": self.failure,
            "knot_interval_s": self.knot_interval,
        }
