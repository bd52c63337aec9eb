"""What a data set holds: the settings every data set shares, and the per-run spec contract.

A :class:`DatasetSpec` is a picklable description of a data set (it travels to local worker
processes and to Dask workers). Its robot-specific subclasses (:class:`~.dh.DhDatasetSpec`
for Aaria DH arms, :class:`~.urdf.UrdfDatasetSpec` for URDF robots) know the data set's fixed
per-run layout (:meth:`DatasetSpec.layout`) and make run k (:meth:`DatasetSpec.make_run`) from
its inputs (:meth:`DatasetSpec.inputs`); the engine (:mod:`.generate`) only calls these, whatever
the robot.

Run k of a data set with seed S is a pure function of (S, k) and the spec: its inputs and its
noise come from its named streams, ``RunSeeds(S, k)`` (:class:`~aaria_pin.core.seeds.RunSeeds`),
so the file is the same, array for array, whatever the number of workers, the scheduler or the
order in which runs finish. The run itself is made by :func:`~.runs.simulate_inputs`.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from aaria_pin._version import __version__
from aaria_pin.aaria.hardware import HardwareConfig
from aaria_pin.aaria.randomize import PARTS, RandomConfig, random_base_table
from aaria_pin.apps.dataset.spec_hardware import HardwareSpec
from aaria_pin.core.arguments import checked
from aaria_pin.core.joint_sensors import CLOSED_LOOP_DRIVES
from aaria_pin.core.record import RunRecord
from aaria_pin.core.se3 import Array
from aaria_pin.core.seeds import DATASET_STREAMS, RunSeeds, check_seed
from aaria_pin.core.trajectory import DEFAULT_DURATION, DEFAULT_RATE
from aaria_pin.errors import AariaError, OutputFileError, ParameterError
from aaria_pin.files.dataset.layout import DatasetLayout, EncodedRun, encode_run, run_arrays

if TYPE_CHECKING:
    from aaria_pin.core.run import Motion, RunRobot, Sensor

__all__ = [
    "MAX_RUNS",
    "MOTIONS",
    "NOISE_STREAM",
    "DatasetJobStoppedError",
    "DatasetSettings",
    "DatasetSpec",
    "Result",
    "RunInputs",
    "check_first_run",
    "run_result",
]

MAX_RUNS = 100_000_000
"""Most runs in one data set."""
MOTIONS = ("sine", "fourier")
"""A data set's joint motions: the joint tables' sines, or a Fourier excitation per run."""
DRIVES = ("motion", *CLOSED_LOOP_DRIVES)
"""A data set's drives: its motions followed, or tracked by a joint controller."""
NOISE_STREAM = DATASET_STREAMS.index("noise")
"""The value of a data set's ``noise_stream`` attribute (3): the spawn-key part of its runs'
noise, which the file records so a reader re-derives a run's noise seed. Streams themselves
come from :class:`~aaria_pin.core.seeds.RunSeeds` only."""


@dataclass(frozen=True)
class RunInputs:
    """What makes one run: its input tables and its noise seed.

    Attributes:
        tables: the input tables by name, as the run records them
        noise_seed: the run's noise stream
    """

    tables: dict[str, Array]
    noise_seed: np.random.SeedSequence

    def describe(self) -> str:
        """The tables as text, for a failed run's message."""
        return " ".join(f"{name}={table.tolist()}" for name, table in self.tables.items())


@checked
@dataclass(frozen=True)
class DatasetSettings:
    """The settings of a data set's runs that do not depend on where its parts come from.

    Shared by the spec (:class:`DatasetSpec`) and its sources (:class:`~.sources.DatasetSources`).

    Attributes:
        n_runs: number of runs N
        seed: seed of the whole data set
        duration: run length [s]
        rate: sample rate [Hz]
        noise: add IMU noise
        dtype: ``"float32"`` or ``"float64"`` for the stored series
        motion: ``"sine"`` (the joint tables) or ``"fourier"``: each run follows a Fourier
            excitation (:func:`~aaria_pin.core.excitation.fourier_excitation`) drawn from its
            ``joints`` stream (:meth:`DatasetSpec.fourier_seed`), stored per run as the table
            ``fourier_coefficients`` (its ``senSenJ``/``joint_table`` is then the robot's
            default, not followed); recorded in the file's ``motion`` and ``fourier``
            attributes
        harmonics: harmonics per joint of a Fourier excitation (default
            :data:`~aaria_pin.core.excitation.DEFAULT_HARMONICS`)
        base_frequency: its base frequency [Hz] (default
            :func:`~aaria_pin.core.excitation.default_base_frequency` of the duration)
        drive: ``"motion"`` (the joints follow the motion) or a closed-loop drive (``"pd"``,
            ``"computed-torque"``): a joint controller tracks the motion through the dynamics
            (:class:`~aaria_pin.core.run.closed_loop.ClosedLoopDrive`), its gains from the
            config's ``[controller]`` table (ranges drawn per run; default
            :class:`~aaria_pin.core.joint_sensors.ControllerModel`); a run whose controller
            loses its reference fails, naming its gains. Recorded in the file's ``drive``
    """

    n_runs: int
    seed: int = 0
    duration: float = DEFAULT_DURATION
    rate: float = DEFAULT_RATE
    noise: bool = True
    dtype: str = "float32"
    motion: str = "sine"
    harmonics: int | None = None
    base_frequency: float | None = None
    drive: str = "motion"


@dataclass(frozen=True)
class DatasetSpec(DatasetSettings, HardwareSpec, ABC):
    """What a data set holds: its settings (:class:`DatasetSettings`) and random parts.

    A subclass adds its robot.

    Attributes:
        config: ranges and probabilities of the random parts
        vary: the random parts, a subset of ``("structure", "joints", "base")``
        joint_table: the fixed joint oscillation table when the joints do not vary (default:
            the robot's default table)
        base_table: the fixed base oscillation table when the base does not vary (default:
            :func:`~aaria_pin.core.oscillation.default_base_table`)
        hardware: the IMU model and the joint models, each number fixed or a range drawn per
            run (:class:`~aaria_pin.aaria.hardware.HardwareConfig`; default the ADIS16485 and
            no joint hardware); recorded in the file's ``noise_parameters``, ``encoder``,
            ``torque_sensor``, ``actuator`` (ranges at their middle), ``hardware`` (the tables)
            and, with ranges, per run the table ``hardware_values`` of the drawn values (their
            attribute paths in ``hardware_names``; a run read back has its own values)
        sensors: sensors beside the IMUs (:mod:`~aaria_pin.core.run.sensor`): each run
            stores the table ``sensor_<name>`` (T × its columns, in the data set's dtype); the
            file's attribute ``sensors`` gives their columns and units
    """

    config: RandomConfig = field(default_factory=RandomConfig)
    vary: tuple[str, ...] = PARTS
    joint_table: Array | None = None
    base_table: Array | None = None
    hardware: HardwareConfig = field(default_factory=HardwareConfig)
    sensors: tuple[Sensor, ...] = ()

    def __post_init__(self) -> None:
        from aaria_pin.core.trajectory import sample_times

        if not (isinstance(self.n_runs, (int, np.integer)) and 1 <= self.n_runs <= MAX_RUNS):
            raise ParameterError(parameter="n_runs", value=self.n_runs, allowed=f"1 to {MAX_RUNS}")
        check_seed(self.seed)
        if self.dtype not in ("float32", "float64"):
            raise ParameterError(parameter="dtype", value=self.dtype, allowed="float32, float64")
        unknown = [part for part in self.vary if part not in PARTS]
        if unknown:
            raise ParameterError(
                parameter="vary", value=unknown[0], element="a part", allowed=", ".join(PARTS)
            )
        sample_times(self.duration, self.rate)  # checks duration and rate
        self._check_motion()

    def _check_motion(self) -> None:
        """Refuse a motion, harmonics or base frequency that no run can use.

        Raises:
            ParameterError: an unknown motion, Fourier settings for sines, a fixed joint table
                with a Fourier excitation, or settings :func:`fourier_excitation` refuses.
        """
        from aaria_pin.core.excitation import fourier_excitation

        if self.motion not in MOTIONS:
            raise ParameterError(parameter="motion", value=self.motion, allowed=", ".join(MOTIONS))
        if self.drive not in DRIVES:
            raise ParameterError(parameter="drive", value=self.drive, allowed=", ".join(DRIVES))
        if self.motion == "sine":
            for name in ("harmonics", "base_frequency"):
                if getattr(self, name) is not None:
                    raise ParameterError(
                        parameter=name,
                        value=getattr(self, name),
                        allowed="only with motion fourier",
                    )
            return
        if self.joint_table is not None:
            raise ParameterError(
                parameter="joint_table",
                value="a joint table",
                allowed="none with a Fourier excitation (it replaces the joint tables)",
            )
        fourier_excitation(1, self.duration, self.rate, **self.fourier_settings())

    def fourier_settings(self) -> dict[str, Any]:
        """``base_frequency`` (resolved) and ``harmonics`` of the Fourier excitation."""
        from aaria_pin.core.excitation import DEFAULT_HARMONICS, default_base_frequency

        return {
            "base_frequency": float(
                default_base_frequency(self.duration)
                if self.base_frequency is None
                else self.base_frequency
            ),
            "harmonics": int(DEFAULT_HARMONICS if self.harmonics is None else self.harmonics),
        }

    def fourier_seed(self, run: int) -> np.random.SeedSequence:
        """The seed of run ``run``'s Fourier coefficients: its ``joints`` stream.

        Run 0's for every run when the joints do not vary.
        """
        drawn = run if "joints" in self.vary else 0
        return RunSeeds(self.seed, drawn).sequence("fourier")

    def run_motion(self, inputs: RunInputs) -> Motion:
        """The engine's motion of a run: its joint table's sines, or its Fourier excitation.

        Tracked by the data set's controller when its ``drive`` is closed-loop.
        """
        from aaria_pin.core.excitation import FourierExcitation
        from aaria_pin.core.run import FourierMotion, SineTable, driven

        motion: Motion = SineTable()
        if self.motion != "sine":
            settings = self.fourier_settings()
            motion = FourierMotion(
                FourierExcitation.from_table(
                    inputs.tables["fourier_coefficients"], settings["base_frequency"], settings
                )
            )
        return driven(motion, {"drive": self.drive})

    def motion_attributes(self) -> dict[str, Any]:
        """``motion`` and ``fourier`` of a Fourier data set, ``drive`` of a closed-loop one.

        Nothing for sines the joints follow (as before).
        """
        drive = {} if self.drive == "motion" else {"drive": self.drive}
        if self.motion == "sine":
            return drive
        return {"motion": self.motion, "fourier": self.fourier_settings(), **drive}

    # --- what a robot adds ----------------------------------------------------------------------

    @property
    @abstractmethod
    def kind(self) -> str:
        """The record kind of the runs (``"dh"``, ``"urdf"``)."""

    @abstractmethod
    def robot_name(self) -> str:
        """The ``robot`` attribute of the runs (a preset or robot name)."""

    @abstractmethod
    def robot_attributes(self) -> dict[str, Any]:
        """What the file records of the robot beyond its name (compared on resume)."""

    @abstractmethod
    def run_robot(self, inputs: RunInputs) -> RunRobot:
        """The engine's robot of a run (its kind's adapter) from the run's input tables."""

    @abstractmethod
    def robot_layout(self) -> DatasetLayout:
        """The robot's fixed per-run layout: joints, IMUs, tables, views, URDF."""

    def layout(self) -> DatasetLayout:
        """The fixed per-run layout: the robot's, a table per extra sensor (T × columns).

        And the tables of the joint hardware and the drawn values
        (:meth:`~.spec_hardware.HardwareSpec.hardware_tables`).
        """
        layout = self.robot_layout()
        hardware = self.hardware_tables(len(layout.joint_names))
        if not self.sensors and not hardware:
            return layout
        from dataclasses import replace

        from aaria_pin.core.run.sensor import sensor_table

        samples = self.samples
        tables = {sensor_table(s.name): (samples, len(s.columns)) for s in self.sensors}
        return replace(layout, tables={**layout.tables, **hardware, **tables})

    @abstractmethod
    def inputs(self, run: int) -> RunInputs:
        """The inputs of run ``run``, a pure function of the seed and ``run``."""

    def check_inputs(self, inputs: RunInputs) -> None:
        """Check a run's input tables on their own, before any simulation.

        The robot's subclass checks its tables; this checks the base table.

        Raises:
            TableError: a table no run can use.
        """
        from aaria_pin.core.oscillation import validate_base_table

        if "senSenB" in inputs.tables:
            validate_base_table(inputs.tables["senSenB"])
        if "base_table" in inputs.tables:
            validate_base_table(inputs.tables["base_table"])

    # --- the same for every robot ---------------------------------------------------------------

    def make_run(self, run: int) -> RunRecord:
        """Run ``run`` as a record, a pure function of the spec and ``run``."""
        from aaria_pin.apps.dataset.runs import simulate_inputs

        return self.with_drawn_values(
            run, simulate_inputs(self, self.inputs(run), self.run_settings(run))
        )

    def arrays(self, run: int) -> dict[str, Array]:
        """The stored arrays of run ``run`` by name, in the data set's dtypes."""
        return run_arrays(self.layout(), self.make_run(run), self.dtype)

    def describe_inputs(self, run: int) -> str:
        """The inputs of a run, for its error message (and the values it drew from ranges)."""
        try:
            return self.inputs(run).describe() + self.describe_drawn(run)
        except Exception:
            return "inputs could not be drawn"

    @property
    def samples(self) -> int:
        """Samples per run T."""
        from aaria_pin.core.trajectory import sample_times

        return int(sample_times(self.duration, self.rate).size)

    def base_and_noise(self, run: int) -> tuple[Array, np.random.SeedSequence]:
        """Base table (6 × 4) and noise seed of run ``run`` (every robot draws them alike)."""
        from aaria_pin.core.oscillation import default_base_table

        seeds = RunSeeds(self.seed, run)
        if "base" in self.vary:
            base_table = random_base_table(self.config, seeds.generator("base"))
        else:
            base_table = np.asarray(
                self.base_table if self.base_table is not None else default_base_table(),
                dtype=float,
            )
        if base_table.shape == (2, 4):
            base_table = np.repeat(base_table, 3, axis=0)
        return base_table, seeds.sequence("noise")

    def attributes(self) -> dict[str, Any]:
        """File attributes describing the spec (what :meth:`mismatches` compares on resume)."""
        from aaria_pin.core.run.sensor import sensor_attributes

        fixed = {
            name: getattr(self, name).tolist()
            for name in self.fixed_table_names()
            if getattr(self, name) is not None
        }
        return {
            "kind": self.kind,
            "robot": self.robot_name(),
            **({"robot_info": info} if (info := self.robot_attributes()) else {}),
            **self.run_settings().attributes(self.seed),
            **sensor_attributes(self.sensors),
            **self.hardware_attributes(),
            "noise_stream": NOISE_STREAM,
            "vary": list(self.vary),
            "config": self.config.as_dict(),
            "fixed_tables": fixed,
            **self.motion_attributes(),
            "version": __version__,
        }

    def fixed_table_names(self) -> tuple[str, ...]:
        """The spec's fields that hold fixed tables (recorded in ``fixed_tables``)."""
        return ("joint_table", "base_table")

    def mismatches(self, stored: dict[str, Any]) -> list[str]:
        """Names of the settings that differ from a stored data set's attributes."""
        mine = {**self.attributes(), "N": self.n_runs, "samples": self.samples, "dtype": self.dtype}
        keys = ("version", "noise_parameters", "N", "samples", "dtype", "seed", "rate",
                "duration", "noise", "vary", "config", "fixed_tables", "kind", "robot",
                "robot_info", "motion", "fourier", "sensors", "hardware", "hardware_names",
                "encoder", "torque_sensor", "actuator", "controller", "current_sensor",
                "drive")  # fmt: skip
        return [key for key in keys if _plain(stored.get(key)) != _plain(mine.get(key))]


Result = tuple[int, EncodedRun | None, str]
"""A run's outcome: its index, its encoded chunks (None if it failed), its error message."""


def run_result(spec: DatasetSpec, run: int) -> Result:
    """A worker's work on one run: its compressed chunks, or its one-line error and inputs.

    Any failure of one run is reported, so the others go on.
    """
    try:
        return run, encode_run(spec.layout(), spec.make_run(run), spec.dtype), ""
    except Exception as exc:
        message = str(exc) if isinstance(exc, AariaError) else f"{type(exc).__name__}: {exc}"
        return run, None, f"{message} ({spec.describe_inputs(run)})"


def _refused(what: str, exc: AariaError) -> ParameterError:
    """``exc`` refused again as "what: exc" on one line, naming the input at fault."""
    return ParameterError(
        f"{what}: {' '.join(str(exc).split())}",
        parameter=exc.parameter or "spec",
        value=exc.value,
        element=exc.element,
    )


def check_first_run(spec: DatasetSpec) -> Result:
    """Check run 0's inputs, then make and encode run 0 (before a data set file is touched).

    Run 0 takes every fixed input (tables, the robot) and one draw of the random ones: a table
    no run can use, or config ranges that draw such a table, are refused here
    (:meth:`DatasetSpec.check_inputs`). When nothing varies, every run has run 0's inputs, so
    run 0 failing on its inputs is refused too.

    Returns:
        Run 0's result (a failed run, as the job records it, when its failure depends on what
        was drawn).

    Raises:
        ParameterError: run 0's inputs are refused, naming them and why.
    """
    try:
        spec.check_inputs(spec.inputs(0))
    except AariaError as exc:
        drawn = f" (its {', '.join(spec.vary)} drawn from the config ranges)" if spec.vary else ""
        raise _refused(f"run 0 of the data set cannot be made{drawn}", exc) from None
    if spec.vary:
        return run_result(spec, 0)
    try:
        record = spec.make_run(0)
    except AariaError as exc:
        raise _refused("no run of the data set can be made", exc) from None
    except Exception:
        return run_result(spec, 0)
    try:
        return 0, encode_run(spec.layout(), record, spec.dtype), ""
    except Exception:
        return run_result(spec, 0)


class DatasetJobStoppedError(OutputFileError):
    """A data-set job stopped before its end (Ctrl-C, no space left, its scheduler lost).

    The output is left incomplete, so it is an :class:`~aaria_pin.errors.OutputFileError`
    (an :class:`OSError` too) whose ``parameter`` is ``path`` and ``value`` the file. The runs
    saved so far are in the file, and the same command with ``--resume`` goes on.

    Args:
        message: the one-line message (what stopped the job, the runs saved)
        saved: runs complete in the file (None: the file cannot be read)
        total: the data set's N
        exit_status: the command's exit status (130 after Ctrl-C, else 1)
        parameter: ``path``, the output of :func:`~.engine.generate_dataset`
        value: the data set file

    Attributes:
        saved: as given
        total: as given
        exit_status: as given
    """

    def __init__(
        self,
        message: str,
        saved: int | None,
        total: int,
        exit_status: int = 1,
        *,
        parameter: str = "path",
        value: str = "",
    ) -> None:
        super().__init__(message, parameter=parameter, value=value)
        self.saved = saved
        self.total = total
        self.exit_status = exit_status


def _plain(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value
