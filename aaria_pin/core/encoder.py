"""Joint encoders: what a run's encoders report, ``q_measured = o + Δ·round((q + n)/Δ)``.

``Δ`` is one count, ``2π/counts_per_revolution`` [rad] for a revolute joint and
``1/counts_per_metre`` [m] for a prismatic one (which joint is which comes from the robot's
model; 0 counts: no quantisation), ``o`` each joint's zero offset, drawn once per run from
``N(0, offset²)``, and ``n`` white noise ``N(0, noise²)`` per sample. So
``(q_measured - o)/Δ`` is a whole number for every sample: the reading is a count of the
encoder's grid, shifted by its offset. With no noise and no offset the reading is ``q``
rounded to the grid; with no counts either, it is ``q`` itself.

An :class:`EncoderStream` is one run's encoders: it draws the offsets when it is made, then the
noise piece by piece in time order (from the run's ``encoder`` stream,
:func:`~aaria_pin.core.seeds.sensor_sequence`), so a run in pieces reads what the run held
whole reads, bit for bit. The record keeps ``q`` (true), ``q_measured`` (T × n) and
``encoder_offset`` (1 × n).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from aaria_pin.core.joint_sensors import EncoderModel, JointColumns, per_joint
from aaria_pin.core.se3 import Array
from aaria_pin.core.seeds import sensor_sequence

__all__ = ["EncoderModel", "EncoderStream", "encoder_reading", "encoder_steps"]


def encoder_steps(model: EncoderModel, prismatic: Array) -> Array:
    """One count of each joint's encoder [rad or m] (0: no quantisation).

    Args:
        model: the encoders
        prismatic: which joints slide, a bool per joint (record order)
    """
    n = prismatic.size
    counts = np.where(
        prismatic,
        per_joint(model.counts_per_metre, n, "counts_per_metre"),
        per_joint(model.counts_per_revolution, n, "counts_per_revolution"),
    )
    full = np.where(prismatic, 1.0, 2.0 * np.pi)
    with np.errstate(divide="ignore"):
        return np.where(counts > 0, full / np.where(counts > 0, counts, 1.0), 0.0)


def encoder_reading(q: Array, offset: Array, step: Array, noise: Array | None = None) -> Array:
    """What the encoders report: ``o + Δ·round((q + n)/Δ)``, or ``q + n + o`` where ``Δ`` is 0.

    The offset ``o`` is where the encoder's zero sits from the joint's: the reading is shifted by
    it (a miscalibrated zero, as identification must find), and it is a whole number of counts
    from ``o``.

    Args:
        q: the true joint values, T × n [rad or m]
        offset: each joint's zero offset ``o``, n [rad or m]
        step: each joint's count ``Δ``, n (0: no quantisation) [rad or m]
        noise: the noise ``n``, T × n (None: none) [rad or m]
    """
    seen = q if noise is None else q + noise
    counted = step > 0
    safe = np.where(counted, step, 1.0)
    return offset + np.where(counted, safe * np.round(seen / safe), seen)


class EncoderStream:
    """One run's encoders: offsets drawn when made, noise drawn piece by piece in time order.

    It is a joint channel of the engine (``core/run/measured.py``): :meth:`tables`,
    :meth:`run_tables`, :meth:`attributes`.

    Args:
        model: the encoders
        prismatic: which joints slide, a bool per joint (record order)
        noise_seed: the run's noise seed; the draws come from its ``encoder`` stream
    """

    name = "encoder"

    def __init__(
        self, model: EncoderModel, prismatic: Array, noise_seed: int | np.random.SeedSequence
    ) -> None:
        n = prismatic.size
        self.model = model
        self.step = encoder_steps(model, prismatic)
        self.sigma = per_joint(model.noise, n, "noise")
        self._generator = np.random.default_rng(sensor_sequence(noise_seed, "encoder"))
        self.offset = per_joint(model.offset, n, "offset") * self._generator.standard_normal(n)

    def tables(self, joints: JointColumns) -> dict[str, Array]:
        """``q_measured`` of the next piece (T × n) [rad or m]."""
        noise = None
        if (self.sigma > 0).any():
            noise = self.sigma * self._generator.standard_normal(joints.q.shape)
        return {"q_measured": encoder_reading(joints.q, self.offset, self.step, noise)}

    def run_tables(self) -> dict[str, Array]:
        """``encoder_offset`` (1 × n) [rad or m]."""
        return {"encoder_offset": self.offset[None, :].copy()}

    def attributes(self) -> dict[str, Any]:
        """None: the model is recorded as the run's ``encoder`` attribute."""
        return {}
