"""A run's joint motion as asked for by name: the joint table's sines, Fourier, or a file.

:class:`MotionChoice` names the motion and its settings; :func:`dh_motion` and
:func:`urdf_motion` make the producer's ``motion`` option of it (and, for a trajectory file,
the run's ``duration`` and ``rate`` where not given). The rules are those of every run: the
Fourier coefficients of a run with seed S come from its ``fourier`` stream
(:class:`~aaria_pin.core.seeds.RunSeeds`), a run re-made from its record keeps the record's
grid; a trajectory file's columns are matched to the robot's and its mimic joints filled by
:func:`~aaria_pin.core.sampled_motion.fit_samples`.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from aaria_pin.core.excitation import FourierExcitation
    from aaria_pin.core.record import RunRecord
    from aaria_pin.core.sampled_motion import JointColumns
    from aaria_pin.core.urdf_robot import UrdfRobot

__all__ = ["MotionChoice", "dh_motion", "urdf_motion"]


_SETTINGS = ("harmonics", "base_frequency", "trajectory", "smoothing")
"""The options of :class:`MotionChoice` beside its kind (``motion``)."""


@dataclass(frozen=True)
class MotionChoice:
    """The joint motion a run is asked to follow; settings of another motion are refused.

    Attributes:
        kind: ``sine`` (the joint table), ``fourier``, ``trajectory`` (a file; the kind of a
            choice given only ``trajectory``), or None (as stored, or the default sines)
        harmonics: harmonics per joint of a Fourier motion (None: the default)
        base_frequency: base frequency of a Fourier motion [Hz] (None: the default)
        trajectory: the file of a trajectory motion (time and one column per joint)
        smoothing: RMS [rad or m] of the noise the trajectory's spline may smooth away (None: 0,
            through every sample)

    Raises:
        OptionConflictError: a trajectory file with another kind (``motion``), Fourier
            settings without the Fourier kind, ``smoothing`` without a trajectory file.
    """

    kind: str | None = None
    harmonics: int | None = None
    base_frequency: float | None = None
    trajectory: Path | None = None
    smoothing: float | None = None

    def __post_init__(self) -> None:
        from aaria_pin.core.conflicts import OptionConflictError

        if self.trajectory is not None:
            if self.kind not in (None, "trajectory"):
                raise OptionConflictError(
                    parameter="motion", other="trajectory", given_with=True, value=self.kind
                )
            object.__setattr__(self, "kind", "trajectory")
        for name, other, kind in (
            ("harmonics", "motion", "fourier"),
            ("base_frequency", "motion", "fourier"),
            ("smoothing", "trajectory", "trajectory"),
        ):
            value = getattr(self, name)
            if value is not None and self.kind != kind:
                shown = kind if other == "motion" else ""
                raise OptionConflictError(
                    parameter=name, other=other, given_with=False, value=value, other_value=shown
                )

    @classmethod
    def from_options(cls, options: Mapping[str, Any]) -> MotionChoice:
        """The choice a run's options name (the other options are left to the caller).

        Args:
            options: ``motion`` (the kind), ``harmonics``, ``base_frequency``, ``trajectory``
                and ``smoothing``; absent or None: not given

        Raises:
            OptionConflictError: as the class.
        """
        settings = {name: options.get(name) for name in _SETTINGS}
        return cls(options.get("motion"), **settings)


def _refuse_with_options(choice: MotionChoice, options: Mapping[str, Any]) -> None:
    """Refuse a motion the run's other options make meaningless.

    Raises:
        OptionConflictError: a motion asked for a run driven by ``torques`` (the torques move
            the joints), a ``joint_table`` (the sines' table) with a Fourier or trajectory
            motion.
    """
    from aaria_pin.core.conflicts import OptionConflictError

    named = "trajectory" if choice.kind == "trajectory" else "motion"
    if choice.kind is not None and options.get("torques") is not None:
        value = str(choice.trajectory) if named == "trajectory" else choice.kind
        raise OptionConflictError(parameter=named, other="torques", given_with=True, value=value)
    if choice.kind in ("fourier", "trajectory") and options.get("joint_table") is not None:
        raise OptionConflictError(
            parameter="joint_table",
            other=named,
            given_with=True,
            value=options["joint_table"],
            other_value="fourier" if named == "motion" else "",
        )


def chosen_motion(
    choice: MotionChoice,
    stored: RunRecord | None,
    options: Mapping[str, Any],
    joints: Callable[[], JointColumns],
    fourier: Callable[[float, float, dict[str, Any]], FourierExcitation],
) -> dict[str, Any]:
    """The producer's ``motion`` (and the time grid of a trajectory file) of a choice.

    Args:
        choice: the motion asked for
        stored: the record a run is re-made from, if any (its grid and seed are the defaults)
        options: the producer's options so far (``duration``, ``rate``, ``seed``)
        joints: the robot's motion columns (called only for a trajectory file)
        fourier: ``(duration, rate, settings) -> FourierExcitation`` of the robot

    Returns:
        ``motion`` (None: back to the joint table's sines, also the choice of a given
        ``joint_table``) and, for a trajectory file, its ``duration`` and ``rate`` where not
        given; nothing when the choice leaves the motion as stored (or as the default sines).

    Raises:
        ParameterError: a trajectory motion without its file, or Fourier settings refused.
        OptionConflictError: a motion with ``torques``, a ``joint_table`` with a Fourier or
            trajectory motion.
        InputFileError: a trajectory file that cannot be read or matched to the joints.
    """
    from aaria_pin.core.run import RunSettings

    _refuse_with_options(choice, options)
    if choice.kind is None and options.get("joint_table") is None:
        return {}
    if choice.kind in (None, "sine"):  # the table given is followed (also by a re-made run)
        return {"motion": None}
    grid = RunSettings.from_attributes(stored.attributes if stored is not None else {})
    rate = options.get("rate", grid.rate)
    if choice.kind == "fourier":
        from aaria_pin.core.seeds import RunSeeds
        from aaria_pin.core.trajectory import MAX_STREAMED_SAMPLES

        stored_seed = stored.metadata.seed if stored else 0
        seed = options.get("seed", getattr(stored_seed, "entropy", stored_seed))
        settings = {
            "base_frequency": choice.base_frequency,
            "harmonics": choice.harmonics,
            "seed": RunSeeds(int(seed)).sequence("fourier"),
            "max_samples": MAX_STREAMED_SAMPLES,
        }
        return {"motion": fourier(options.get("duration", grid.duration), rate, settings)}
    from aaria_pin.core.sampled_motion import GivenSamples, fit_samples
    from aaria_pin.files.trajectory_file import read_trajectory_file

    path = choice.trajectory
    if path is None:
        from aaria_pin.errors import ParameterError

        raise ParameterError(parameter="trajectory", value=None, allowed="the motion's file")
    time, q, qd, qdd, names = read_trajectory_file(path)
    trajectory, duration, file_rate = fit_samples(
        GivenSamples(str(path), time, q, qd, qdd, names),
        joints(),
        rate=options.get("rate"),
        duration=options.get("duration"),
        fallback_rate=grid.rate,
        smoothing=choice.smoothing or 0.0,
    )
    return {"motion": trajectory, "duration": duration, "rate": file_rate}


def dh_motion(
    choice: MotionChoice, stored: RunRecord | None, options: Mapping[str, Any], dh_table: Any
) -> dict[str, Any]:
    """:func:`chosen_motion` for a DH arm of ``dh_table`` (six module columns)."""
    from aaria_pin.aaria.arm_run import dh_joint_columns
    from aaria_pin.aaria.simulate import dh_fourier_excitation

    def fourier(duration: float, rate: float, settings: dict[str, Any]) -> FourierExcitation:
        return dh_fourier_excitation(dh_table, duration, rate, **settings)

    return chosen_motion(choice, stored, options, lambda: dh_joint_columns(dh_table), fourier)


def urdf_motion(
    choice: MotionChoice,
    stored: RunRecord | None,
    options: Mapping[str, Any],
    urdf: str = "",
    urdf_dir: Path | None = None,
) -> dict[str, Any]:
    """:func:`chosen_motion` for a URDF robot: the stored run's, else that of ``urdf``.

    Args:
        choice: the motion asked for
        stored: the record a run is re-made from (its URDF and folder), if any
        options: the producer's options so far (also ``tool_frame`` and ``imu_layout``)
        urdf: the URDF text (without ``stored``)
        urdf_dir: its folder, for relative mesh paths

    The robot is loaded only if the motion needs it (a Fourier motion or a trajectory file).
    """
    from aaria_pin.core.run.urdf_kind import urdf_joint_columns
    from aaria_pin.core.urdf_robot import load_urdf_robot
    from aaria_pin.core.urdf_run import urdf_fourier_excitation

    def load() -> UrdfRobot:
        if stored is not None:
            folder = stored.metadata.urdf_dir
            return load_urdf_robot(stored.urdf, urdf_dir=Path(folder) if folder else None)
        return load_urdf_robot(
            urdf,
            urdf_dir=urdf_dir,
            tool_frame=options.get("tool_frame"),
            imu_layout=options.get("imu_layout"),
        )

    def fourier(duration: float, rate: float, settings: dict[str, Any]) -> FourierExcitation:
        return urdf_fourier_excitation(load(), duration, rate, **settings)

    return chosen_motion(choice, stored, options, lambda: urdf_joint_columns(load()), fourier)
