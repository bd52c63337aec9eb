"""What the kinematic identification measures, as one typed value: from a run or a recording.

:class:`ArmSignals` holds what a real set-up gives the estimator and nothing else: the sample
times, the joint values by module, every IMU's signals at those times, each IMU's name and the
link it sits on, and the noise model the signals are weighted by. Two constructors make it:

- :meth:`ArmSignals.of_record`: a simulated DH run (``read_run``, a data set's run,
  ``simulate_run``): its one time axis, ``q``, ``imu``, each mount's parent, its noise flag and
  ``noise_parameters``; the record kept as the truth (``senSenDH``) for the errors.
- :meth:`ArmSignals.of_recorded`: a :class:`~aaria_pin.core.recording.RecordedRun` (``aaria
  import``, a bag, an MCAP file, a CSV), each sensor at its own stamps, no truth. The arm's
  structure comes from the IMU names Aaria uses and ``aaria export`` writes (:func:`imu_parent`:
  ``imu_base`` on the base, ``imu_tool`` at the tool tip, ``imu_link<k>_a``/``_b`` on module
  k's link) and the joint names (``joint<k>``: module k; a module without a joint column is
  empty, q = 0).

The time axis of a recording is the base IMU's stamps (its signals are the model's inputs, used
as measured), cut to the span every other stream covers. A stream whose stamps are the base's
(within :data:`SAME_STAMPS` of a period) enters as it is. Others are **resampled** at the base's
stamps by a quintic interpolating spline through their own samples: the joint values with their
velocities and accelerations (each the derivative on the joint stream's own axis, then
interpolated), an IMU at another rate or with its own jitter its six signals. The fit itself
takes one time axis for every IMU (:class:`~aaria_pin.apps.identify.geometry_model.KinematicData`),
so the model is not evaluated at an IMU's own stamps; the resampling's error is estimated per
IMU and said in :attr:`ArmSignals.notes` (the spline through every other sample of the IMU's
own stream, against the samples left out, divided by 2⁶: a quintic spline's error falls as the
sixth power of the spacing; on noisy signals it measures the noise instead, an upper bound).

The noise model of a recording: the one given (a dict of ``noise_parameters`` as a simulated run
stores them), else ADIS16485's (as for a run without ``noise_parameters``). A recording says
nothing of its noise, so its white noise is measured (:func:`white_noise_level`: each sample
against the quintic through its six neighbours, on its own stamps): below
:data:`NOISE_FREE` of the model's level the recording is taken as noise-free (a simulated run
exported without noise: its fit goes to the rounding floor), else as noisy with that model.
:attr:`ArmSignals.noise_model` says which, in words.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

import numpy as np

from aaria_pin.apps.identify.geometry_signals import (
    derivatives,
    rounding_level,
    sample_derivatives,
    signal_weights,
    uniform_time,
)
from aaria_pin.core.record import RunRecord
from aaria_pin.core.recording import RecordedRun, SensorStream
from aaria_pin.core.se3 import Array
from aaria_pin.errors import ParameterError

__all__ = [
    "BASE_PARENT",
    "NOISE_FREE",
    "SAME_STAMPS",
    "TOOL_PARENT",
    "ArmSignals",
    "imu_parent",
    "measured_rates",
    "white_noise_level",
]

BASE_PARENT = "base"
"""The parent of the base IMU (its frame is the base frame)."""

TOOL_PARENT = "tool_tip"
"""The parent of the tool IMU (its frame is the tool-tip frame)."""

SAME_STAMPS = 0.01
"""A stream whose stamps are within this share of the base IMU's period of the base's stamps
is on the base's time axis (taken as it is, not resampled)."""

NOISE_FREE = 0.01
"""A recording whose measured white noise is below this share of the noise model's is taken as
noise-free (a simulated run's: ~1e-7 of ADIS16485's when stored in float32)."""

_IMU_NAMES = "imu_base, imu_tool, imu_link<k>_a, imu_link<k>_b (k 1 to 6)"
_LINK_IMU = re.compile(r"imu_link([1-6])_[ab]")
_JOINT = re.compile(r"joint([1-6])")
_EVEN = 1e-6  # [of a step] a time axis whose steps differ by less is even
_LEFT_OUT = 2**6  # a quintic spline's error at half the spacing, against every other sample


@dataclass(frozen=True)
class ArmSignals:
    """A DH arm's measured signals on one time axis: what kinematic identification takes.

    Attributes:
        time: (N,) sample times [s]
        q: (N, 6) joint values by module [rad or m] (an empty module's column: 0)
        imu: (N, n, 6) every IMU's signals at ``time`` (``wx wy wz`` [rad/s], ``fx fy fz``
            [m/s²]); slots of a run with no IMU (parent ``""``) too
        imu_names: the n IMUs' names
        parents: each IMU's link (``base``, ``tool_tip``, ``link<k>``; ``""``: no IMU)
        noisy: whether the signals carry sensor noise (else they are exact but for rounding)
        noise_parameters: the noise model (as a run's ``noise_parameters``), or None: ADIS16485
        noise_model: the noise model in words (what the output says was assumed)
        joint_rates: (qd, qdd), each (N, 6), when the joints were resampled at ``time``; None:
            the derivatives of ``q`` at ``time``
        truth: the simulated run, for the errors against its true table; None for a recording
        notes: what was resampled, with its estimated error, one line each
    """

    time: Array
    q: Array
    imu: Array
    imu_names: tuple[str, ...]
    parents: tuple[str, ...]
    noisy: bool
    noise_parameters: dict[str, Any] | None
    noise_model: str
    joint_rates: tuple[Array, Array] | None = None
    truth: RunRecord | None = None
    notes: tuple[str, ...] = ()

    @property
    def n_samples(self) -> int:
        """The number of samples N."""
        return int(self.time.size)

    @classmethod
    def of_record(cls, record: RunRecord) -> ArmSignals:
        """The signals of a simulated DH run (its time axis rebuilt: :func:`uniform_time`).

        Raises:
            ParameterError: not a DH run, or not 6 joint columns (parameter ``record``).
        """
        kind = record.attributes.get("kind", "dh")
        if kind != "dh":
            robot = record.attributes.get("robot", "")
            raise ParameterError(
                f"record is a {kind} run{f' of {robot}' if robot else ''}; allowed: a DH arm's "
                "run (aaria dataset, or aaria simulate --preset/--dh): kinematic identification "
                "finds an Aaria arm's extended DH table; for a URDF robot's inertial parameters, "
                "see aaria identify --dynamics",
                parameter="record",
                value=kind,
                allowed="a DH arm's run",
            )
        if record.q.shape[1] != 6:
            raise ParameterError(
                f"record has {record.q.shape[1]} joint columns; allowed: 6 (a DH run by module)",
                parameter="record",
                value=record.q.shape[1],
                allowed="6 joint columns",
            )
        noisy = bool(record.metadata.noise)
        parameters = record.metadata.extra.get("noise_parameters")
        parameters = parameters if isinstance(parameters, dict) else None
        if not noisy:
            described = "none (a noise-free run)"
        else:
            described = "the run's" if parameters is not None else "ADIS16485 (assumed)"
        return cls(
            uniform_time(np.asarray(record.time, dtype=float)),
            np.asarray(record.q),
            np.asarray(record.imu),
            tuple(record.imu_names),
            tuple(mount.parent for mount in record.imu_mounts),
            noisy,
            parameters,
            described,
            truth=record,
        )

    @classmethod
    def of_recorded(
        cls,
        recording: RecordedRun,
        noise_parameters: dict[str, Any] | None = None,
        noise_name: str = "the given model",
    ) -> ArmSignals:
        """The signals of a recording on the base IMU's stamps (module docstring).

        Args:
            recording: the recorded run (``open_recorded``)
            noise_parameters: its IMUs' noise model (a run's ``noise_parameters``); None:
                ADIS16485's
            noise_name: that model's name in the output (with ``noise_parameters``)

        Raises:
            ParameterError: an IMU name outside the scheme (:func:`imu_parent`), no
                ``imu_base`` or ``imu_tool``, no joint stream (or several), a joint name
                outside ``joint1`` to ``joint6``, no joint values, an IMU on a module whose
                joint is not recorded, streams without a common span (parameter
                ``recording``).
        """
        imus = recording.of_kind("imu")
        parents = tuple(imu_parent(stream.name) for stream in imus)
        defined = ((BASE_PARENT, "imu_base", "base"), (TOOL_PARENT, "imu_tool", "tool-tip"))
        for parent, name, frame in defined:
            if parent not in parents:
                names = ", ".join(s.name for s in imus) or "none"
                raise _refused(f"recording has no IMU {name} (IMUs: {names}); allowed: an {name}"
                               f" stream, the IMU whose frame is the {frame} frame")  # fmt: skip
        base = imus[parents.index(BASE_PARENT)]
        joints = _joint_stream(recording)
        recorded = _joint_modules(joints)
        for stream, parent in zip(imus, parents, strict=True):
            if parent.startswith("link") and int(parent[4:]) not in recorded.values():
                raise _refused(
                    f"IMU {stream.name} is on module {parent[4:]}, whose joint{parent[4:]} is not "
                    f"in the joint states; allowed: an IMU on a module whose joint is recorded "
                    f"({', '.join(f'joint{m}' for m in sorted(recorded.values()))})"
                )
        keep, time = _common_axis(base.time, [*imus, joints])
        period = float(np.median(np.diff(base.time)))
        notes: list[str] = []
        signals = []
        for stream in imus:
            values, note = _on_axis(stream, base.time, keep, period)
            signals.append(values)
            notes += [note] if note else []
        q, joint_rates, note = _joint_values(joints, base.time, keep, period)
        notes += [note] if note else []
        imu = np.stack(signals, axis=1)
        rate = (time.size - 1) / max(float(time[-1] - time[0]), 1e-300)
        model_level = 1.0 / signal_weights(rate, noise_parameters)
        measured = np.concatenate([white_noise_level(s.time, s.values) for s in imus])
        ratio = float(np.median(measured / np.tile(model_level, len(imus))))
        name = noise_name if noise_parameters is not None else "ADIS16485"
        if ratio < NOISE_FREE:
            described = (
                f"none: the measured white noise is {ratio:.2g} of {name}'s (below "
                f"{NOISE_FREE:g}: a noise-free recording)"
            )
        else:
            how = "given" if noise_parameters is not None else "assumed: a recording holds none"
            described = f"{name} ({how}; its measured white noise is {ratio:.2g} of the model's)"
        return cls(
            time,
            q,
            imu,
            tuple(s.name for s in imus),
            parents,
            ratio >= NOISE_FREE,
            noise_parameters,
            described,
            joint_rates,
            notes=tuple(notes),
        )


def _refused(message: str) -> ParameterError:
    """A recording the kinematic identification cannot take (parameter ``recording``)."""
    return ParameterError(message, parameter="recording")


def imu_parent(name: str) -> str:
    """The link an IMU of Aaria's naming sits on: ``base``, ``tool_tip`` or ``link<k>``.

    Raises:
        ParameterError: a name outside ``imu_base``, ``imu_tool``, ``imu_link<k>_<a|b>``.
    """
    if name == "imu_base":
        return BASE_PARENT
    if name == "imu_tool":
        return TOOL_PARENT
    link = _LINK_IMU.fullmatch(name)
    if link is None:
        raise _refused(f"IMU name is {name}; allowed: {_IMU_NAMES}")
    return f"link{link.group(1)}"


def _joint_stream(recording: RecordedRun) -> SensorStream:
    """The recording's one joint stream, with joint values.

    Raises:
        ParameterError: none, several, or no ``q`` columns.
    """
    streams = recording.of_kind("joints")
    if len(streams) != 1:
        raise _refused(
            f"recording has {len(streams)} joint state streams; allowed: one (JointStates, "
            "joint<k> the joint of module k)"
        )
    if not any(column.startswith("q:") for column in streams[0].columns):
        raise _refused(
            f"joint stream {streams[0].name} has no joint positions; allowed: JointStates with "
            "positions"
        )
    return streams[0]


def _joint_modules(stream: SensorStream) -> dict[int, int]:
    """The module (1 to 6) of each joint value column of a joint stream, by column index.

    Raises:
        ParameterError: a joint name outside ``joint1`` to ``joint6``.
    """
    modules = {}
    for index, column in enumerate(stream.columns):
        group, _, joint = column.partition(":")
        if group == "q":
            module = _JOINT.fullmatch(joint)
            if module is None:
                raise _refused(f"joint name is {joint}; allowed: joint1 to joint6 (module k)")
            modules[index] = int(module.group(1))
    return modules


def _same_stamps(time: Array, reference: Array, period: float) -> bool:
    """Whether a stream's stamps are the reference's, within :data:`SAME_STAMPS` of a period."""
    return time.size == reference.size and bool(
        np.max(np.abs(time - reference)) <= SAME_STAMPS * period
    )


def _common_axis(reference: Array, streams: list[SensorStream]) -> tuple[Array, Array]:
    """The reference stamps within every resampled stream's span: the mask and the times.

    Raises:
        ParameterError: fewer than two stamps in common.
    """
    period = float(np.median(np.diff(reference)))
    keep = np.ones(reference.size, dtype=bool)
    for stream in streams:
        if not _same_stamps(stream.time, reference, period):
            keep &= (reference >= stream.time[0]) & (reference <= stream.time[-1])
    if np.count_nonzero(keep) < 2:
        raise _refused(
            "recording's streams share no time span; allowed: IMUs and joint states recorded "
            "over a common span"
        )
    return keep, _stored_grid(reference[keep])


def _stored_grid(time: Array) -> Array:
    """A recording's stamps, or the even grid they round when every one is a float32 number.

    Such stamps are a run stored in float32 and exported (to whole nanoseconds: within 1 ns of
    a float32 number; :func:`uniform_time` rebuilds them). A recording's own float64 stamps
    stay as they are: 4 float32 roundings at 3600 s are 1 ms, beyond a real jitter.
    """
    if float(np.max(np.abs(time - time.astype(np.float32)))) <= 1e-9:
        return uniform_time(time)
    return time


def _spline(time: Array, values: Array) -> Any:
    """A quintic interpolating spline through samples (lower order with fewer than six)."""
    from scipy.interpolate import make_interp_spline

    return make_interp_spline(time, values, k=min(5, time.size - 1), axis=0)


def _on_axis(
    stream: SensorStream, reference: Array, keep: Array, period: float
) -> tuple[Array, str]:
    """An IMU's signals at the kept reference stamps, and the note of a resampling (or "")."""
    if _same_stamps(stream.time, reference, period):
        return stream.values[keep], ""
    values = _spline(stream.time, stream.values)(reference[keep])
    if rounding_level(stream.values) is not None:  # stored in float32: as precise again
        values = values.astype(np.float32).astype(float)
    gyro, accel = _resampling_error(stream.time, stream.values)
    return values, (
        f"{stream.name} resampled at imu_base's stamps ({stream.rate:.4g} Hz, own stamps) by a "
        f"quintic spline: estimated error {gyro:.2g} rad/s, {accel:.2g} m/s^2"
    )


def _resampling_error(time: Array, values: Array) -> tuple[float, float]:
    """The largest gyroscope and accelerometer error of resampling (module docstring)."""
    if time.size < 14:
        return float("nan"), float("nan")
    half = _spline(time[::2], values[::2])(time[1:-1:2])
    error = np.max(np.abs(half - values[1:-1:2]), axis=0) / _LEFT_OUT
    return float(np.max(error[:3])), float(np.max(error[3:]))


def _joint_values(
    stream: SensorStream, reference: Array, keep: Array, period: float
) -> tuple[Array, tuple[Array, Array] | None, str]:
    """The joint values by module at the kept stamps, their rates when resampled, the note."""
    q = np.zeros((stream.time.size, 6))
    for index, module in _joint_modules(stream).items():
        q[:, module - 1] = stream.values[:, index]
    if _same_stamps(stream.time, reference, period):
        return q[keep], None, ""
    time = _stored_grid(stream.time)
    rates = measured_rates(time, q, 2)
    at = reference[keep]
    resampled = [_spline(time, values)(at) for values in (q, *rates)]
    return (
        resampled[0],
        (resampled[1], resampled[2]),
        (
            f"joint states resampled at imu_base's stamps ({stream.rate:.4g} Hz, own stamps): "
            "positions, velocities and accelerations by quintic splines"
        ),
    )


def measured_rates(time: Array, values: Array, order: int) -> list[Array]:
    """The first ``order`` derivatives of noise-free samples, on an even axis or not.

    On an even time axis (a run's) as :func:`sample_derivatives` takes them (float32 rounding
    smoothed by Savitzky–Golay filters, which assume even steps). On a recording's jittered
    stamps, float64 values by the quintic spline through them (:func:`derivatives`); float32
    values would carry their rounding into the spline's second derivative times ~1/step² (a
    3-module arm at 200 Hz with 1 ms of jitter: joint accelerations 0.013 rad/s² off, the tool
    tip 0.26 mm), so they are interpolated on the even grid of their span, stored in float32
    again (as precise as they were), differentiated there as a run's, and the derivatives
    interpolated back at the stamps (that arm: within 0.1 mm).
    """
    steps = np.diff(time)
    if not steps.size or np.max(np.abs(steps - np.median(steps))) <= _EVEN * np.median(steps):
        return sample_derivatives(time, values, order)
    if rounding_level(values) is None:
        return derivatives(time, values, order)
    grid = np.linspace(time[0], time[-1], time.size)
    even = _spline(time, values)(grid).astype(np.float32).astype(float)
    return [_spline(grid, rate)(time) for rate in sample_derivatives(grid, even, order)]


def white_noise_level(time: Array, values: Array) -> Array:
    """Per column, the white noise's per-sample standard deviation, measured on the samples.

    Each sample is predicted by the quintic through its six neighbours (three on either side,
    on the stream's own stamps, so jitter does not count as noise); the prediction's error is
    the noise (times ``√(1 + Σ w²)``, ``w`` the prediction's weights) plus the signal's sixth
    derivative times ~h⁶, far below any sensor's noise at the rates IMUs run. The median of
    the squared errors (÷ 0.4549, the median of a χ²₁) keeps motion spikes out.

    Args:
        time: (N,) stamps [s], strictly increasing
        values: (N, C) samples

    Returns:
        (C,) levels [units of values]; zeros with fewer than 7 samples.
    """
    n = time.size
    if n < 7:
        return np.zeros(values.shape[1])
    centre = np.arange(3, n - 3)
    offsets = (-3, -2, -1, 1, 2, 3)
    weights = []
    for j in offsets:
        w = np.ones(centre.size)
        for m in offsets:
            if m != j:
                w *= (time[centre] - time[centre + m]) / (time[centre + j] - time[centre + m])
        weights.append(w)
    predicted = sum(w[:, None] * values[centre + j] for w, j in zip(weights, offsets, strict=True))
    gain = np.sqrt(1.0 + sum(w**2 for w in weights))
    error = (values[centre] - predicted) / gain[:, None]
    return np.sqrt(np.median(error**2, axis=0) / 0.4549)
