"""``aaria identify`` as one library call: which identification, of which files, to which outputs.

An :class:`IdentifyRequest` names the mode (the kinematics of one run, the dynamics of one run,
or the benchmark over data sets) and the options; options of another mode are refused when the
request is made (never silently ignored). :func:`identify_files` checks the outputs before any
work, reads the run (a run file, or run K of a data set), identifies, writes the outputs and
returns the report (JSON types) and its text.

Example::

    from pathlib import Path
    from aaria_pin.apps.identify.request import IdentifyRequest, identify_files

    outcome = identify_files(IdentifyRequest((Path("run.h5"),), dynamics=True, holdout=0.3))
    for line in outcome.lines:
        print(line)
"""

from __future__ import annotations

import json
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from aaria_pin.errors import OutputFileError, ParameterError

if TYPE_CHECKING:
    from aaria_pin.apps.identify.benchmark import RunAccuracy
    from aaria_pin.apps.identify.geometry_result import KinematicIdentification

__all__ = ["DEFAULT_HOLDOUT", "IdentifyOutcome", "IdentifyRequest", "identify_files"]

DEFAULT_HOLDOUT = 0.2
"""Share of a run, at its end, held out of the dynamic fit when the request gives none."""

_TABLE_HEADER = (
    "estimated Aaria DH table (aaria identify): alpha [rad], a [m], theta [rad], d [m], "
    "link type; rows 1-6 modules, 7 tool, 8 base"
)


@dataclass(frozen=True)
class IdentifyRequest:
    """What to identify and where the results go.

    Attributes:
        files: one run file or data set; in the data-set mode, data sets of DH arms
        dynamics: the inertial base parameters from the torques (with ``dataset``: as well)
        dataset: the benchmark: identify every run of the data sets ``files``
        run: the run of a data set (one-run modes)
        output: the estimated 8 × 5 DH table (``.csv``; kinematics), else the JSON report
        urdf: the estimated arm with its IMUs at their estimated mounts (``.urdf``; kinematics)
        holdout: share of each run held out of the dynamic fit (dynamics; default
            :data:`DEFAULT_HOLDOUT`)
        parameters: a text line for every base parameter (dynamics of one run)
        torques: the joint torques fitted (dynamics of one run; ``auto``, ``measured``,
            ``current``, ``motor``, ``rigid``: :mod:`~aaria_pin.apps.identify.inertial_torques`)
        torque_constant: the motors' torque constant [N·m/A] (``current``; None: the run's)
        gear_ratio: the gearboxes' ratio [1] (``current``; None: the run's)
        friction: fit friction and armature (dynamics of one run; None: when the torques
            hold them)
        consistent: physically consistent bodies (dynamics of one run)
        dynamics_urdf: the run's URDF with the identified dynamics (``.urdf``; dynamics of
            one run; the fit is then consistent)
        workers: processes (data-set mode; default 1)
        limit: at most this many runs of each data set (data-set mode)
        plot: where the caller draws the tool-tip error CDF (data-set mode; only checked here,
            :func:`~aaria_pin.apps.identify.benchmark.tool_tip_cdf` gives its curves)
        rigid: IMU pairs (A, B) on one rigid body each: B's pose and time offset relative to
            A from a recording's signals alone (:mod:`~aaria_pin.apps.identify.bodies`)
        joint: IMU pairs (A, B) on two bodies: the joint between them (type, axis, point)
        imu_model: the recording's IMUs (a preset name or an IMU-model TOML file; kinematics
            of a recording; None: ADIS16485's, said in the output): the fit's weights and bias
            knots
        log: write a line per stage, per start of a kinematic fit and per run of the data-set
            mode to stderr (``aaria: identify: ...``; plain lines, a log keeps them)
        start: a start table for the kinematic fit (kinematics of one run): an 8 × 5 table
            file the DH readers read (``.npy``, CSV such as ``-o``'s, ``.mat``, a run file;
            :func:`~aaria_pin.files.io.read_table`), its use in
            :mod:`~aaria_pin.apps.identify.geometry_warm`

    Raises:
        ParameterError: no file, or several files outside the data-set mode.
        OptionConflictError: an option of another mode (its ``parameter`` names it, its
            ``other`` the mode's option: ``holdout`` without ``dynamics``).
    """

    files: tuple[Path, ...]
    dynamics: bool = False
    dataset: bool = False
    run: int | None = None
    output: Path | None = None
    urdf: Path | None = None
    holdout: float | None = None
    parameters: bool = False
    torques: str = "auto"
    friction: bool | None = None
    consistent: bool = False
    dynamics_urdf: Path | None = None
    workers: int | None = None
    limit: int | None = None
    plot: Path | None = None
    torque_constant: float | None = None
    gear_ratio: float | None = None
    rigid: tuple[tuple[str, str], ...] = ()
    joint: tuple[tuple[str, str], ...] = ()
    imu_model: str | None = None
    log: bool = False
    start: Path | None = None

    @property
    def progress(self) -> Callable[[str], None] | None:
        """The stderr line writer of :attr:`log`, or None."""
        if not self.log:
            return None

        def line(text: str) -> None:
            sys.stderr.write(f"aaria: identify: {text}\n")
            sys.stderr.flush()

        return line

    def __post_init__(self) -> None:
        files = len(self.files)
        if files == 0:
            raise ParameterError(
                "no FILE given; allowed: a run file, or data sets in the data-set mode",
                parameter="files",
                value=0,
                allowed="a run file, or data sets in the data-set mode",
            )
        if not self.dataset and files > 1:
            raise ParameterError(
                f"{files} files given; allowed: one run file, or data sets in the data-set mode",
                parameter="files",
                value=files,
                allowed="one run file, or data sets in the data-set mode",
            )
        self._refuse_conflicts()

    def _refuse_conflicts(self) -> None:
        """Refuse an option of another mode (it would be ignored), naming the mode's option."""
        from aaria_pin.core.conflicts import OptionConflictError

        for parameter, given, other, given_with in (
            ("run", self.run is not None, "dataset", True),  # the data sets' every run
            ("urdf", self.urdf is not None, "dynamics", True),
            ("urdf", self.urdf is not None, "dataset", True),
            ("holdout", self.holdout is not None, "dynamics", False),
            ("parameters", self.parameters, "dataset", True),
            ("parameters", self.parameters, "dynamics", False),
            *(
                (name, given, mode, mode == "dataset")
                for name, given in (
                    ("torques", self.torques != "auto"),
                    ("friction", self.friction is not None),
                    ("consistent", self.consistent),
                    ("dynamics_urdf", self.dynamics_urdf is not None),
                    ("torque_constant", self.torque_constant is not None),
                    ("gear_ratio", self.gear_ratio is not None),
                )
                for mode in ("dynamics", "dataset")
            ),
            *(  # k_t and N turn currents into torques: meaningless with the other torques
                (name, given and self.torques in ("rigid", "measured", "motor"), "torques", True)
                for name, given in (
                    ("torque_constant", self.torque_constant is not None),
                    ("gear_ratio", self.gear_ratio is not None),
                )
            ),
            *(  # the IMUs of a recording's kinematics, not of another mode
                ("imu_model", self.imu_model is not None, mode, True)
                for mode in ("dynamics", "dataset", "rigid", "joint")
            ),
            *(  # a start table of one run's kinematic fit
                ("start", self.start is not None, mode, True)
                for mode in ("dynamics", "dataset", "rigid", "joint")
            ),
            ("workers", self.workers is not None, "dataset", False),
            ("limit", self.limit is not None, "dataset", False),
            ("plot", self.plot is not None, "dataset", False),
            *(  # the IMU-pair modes take a recording and no option of another mode
                (name, given, mode, True)
                for name, given in (
                    ("dynamics", self.dynamics),
                    ("dataset", self.dataset),
                    ("urdf", self.urdf is not None),
                    ("holdout", self.holdout is not None),
                    ("parameters", self.parameters),
                    ("consistent", self.consistent),
                )
                for mode in ("rigid", "joint")
            ),
        ):
            if given and bool(getattr(self, other)) == given_with:
                value = getattr(self, parameter)
                value = str(value) if isinstance(value, Path) else value
                raise OptionConflictError(
                    parameter=parameter,
                    other=other,
                    given_with=given_with,
                    value=value,
                    other_value=self.torques if other == "torques" else "",
                )

    @property
    def bodies(self) -> bool:
        """IMUs on rigid bodies and joints between them (``rigid`` or ``joint`` given)."""
        return bool(self.rigid or self.joint)


@dataclass(frozen=True)
class IdentifyOutcome:
    """What :func:`identify_files` found.

    Attributes:
        report: the report, JSON types (what ``--json`` prints and ``-o`` holds in the
            dynamics and data-set modes)
        lines: the report as text lines
        runs: the data-set mode's per-run results (else empty)
        groups: the data-set mode's accuracy table (else empty)
        failure: why the kinematic fit is not a result (one line; nothing written), or None
    """

    report: dict[str, Any]
    lines: tuple[str, ...]
    runs: tuple[RunAccuracy, ...] = ()
    groups: tuple[dict[str, Any], ...] = field(default=())
    failure: str | None = None


def _check_output(path: Path | None, parameter: str, what: str, suffix: str) -> None:
    """Refuse an output of another type, or one that cannot be written (nothing touched)."""
    if path is None:
        return
    from aaria_pin.files.paths import check_output

    if path.suffix.lower() != suffix:
        raise OutputFileError(parameter=parameter, value=str(path), allowed=f"a {what} ({suffix})")
    check_output(path, suffixes=(suffix,))


def _write_json(path: Path | None, report: dict[str, Any]) -> None:
    if path is not None:
        from aaria_pin.files.io import write_text_atomic

        write_text_atomic(path, json.dumps(report) + "\n")


def _write_kinematics(result: KinematicIdentification, request: IdentifyRequest) -> None:
    from aaria_pin.files.io import atomic_output, write_text_atomic

    if request.output is not None:
        import numpy as np

        with atomic_output(request.output) as temporary:
            np.savetxt(temporary, result.table, delimiter=",", fmt="%.17g", header=_TABLE_HEADER)
    if request.urdf is not None:
        from aaria_pin.aaria.dh_robot import build_dh_robot

        poses = [mount.T_parent_imu for mount in result.mounts]
        robot = build_dh_robot(result.table, imu_mount=poses, name="aaria_identified")
        write_text_atomic(request.urdf, robot.urdf)


def _benchmark(request: IdentifyRequest) -> IdentifyOutcome:
    from aaria_pin.apps.identify.benchmark import (
        accuracy_lines,
        accuracy_table,
        benchmark_datasets,
    )

    say = request.progress
    done: list[RunAccuracy] = []

    def arrived(run: RunAccuracy) -> None:
        done.append(run)
        if say is not None:
            what = run.error or (
                f"tool tip RMS {run.tool_tip_rms * 1e3:.3g} mm, link types "
                f"{'right' if run.link_types_right else 'wrong'}"
            )
            say(f"run {len(done)} done ({run.dataset} run {run.run}): {what}, {run.seconds:.1f} s")

    runs = benchmark_datasets(
        request.files,
        workers=request.workers or 1,
        dynamics=request.dynamics,
        limit=request.limit,
        progress=arrived,
        holdout=DEFAULT_HOLDOUT if request.holdout is None else request.holdout,
    )
    groups = accuracy_table(runs)
    report = {"groups": groups, "runs": [r.to_json() for r in runs]}
    _write_json(request.output, report)
    lines = accuracy_lines(groups) + [
        f"{r.dataset} run {r.run}: {r.error}" for r in runs if r.error is not None
    ]
    return IdentifyOutcome(report, tuple(lines), tuple(runs), tuple(groups))


def _bodies(request: IdentifyRequest) -> IdentifyOutcome:
    from aaria_pin.apps.identify.bodies import identify_bodies
    from aaria_pin.apps.recordings import open_recorded

    _check_output(request.output, "output", "JSON report", ".json")
    found = identify_bodies(open_recorded(request.files[0], request.run), request.rigid,
                            request.joint)  # fmt: skip
    if found.failure is None:
        _write_json(request.output, found.report)
    return IdentifyOutcome(found.report, found.lines, failure=found.failure)


def _noise_parameters(imu_model: str | None) -> dict[str, Any] | None:
    """The noise terms of ``imu_model`` (a preset or a TOML file) as a run records them."""
    if imu_model is None:
        return None
    from aaria_pin.aaria.hardware import imu_model_option
    from aaria_pin.core.imu_noise import noise_attributes

    return noise_attributes(imu_model_option(imu_model))


def _start_table(path: Path) -> Any:
    """The start table of a file (a DH reader's), its read errors naming ``start``."""
    from aaria_pin.errors import InputFileError
    from aaria_pin.files.io import read_table

    try:
        return read_table(path, "senSenDH")
    except InputFileError as error:
        raise InputFileError(f"start {error}", parameter="start", value=str(path)) from None


def _kinematics(request: IdentifyRequest) -> IdentifyOutcome:
    """The DH table of a simulated run, or of a recording (its noise model said first)."""
    from aaria_pin.apps.identify.geometry import identify_kinematics
    from aaria_pin.apps.identify.geometry_input import ArmSignals
    from aaria_pin.apps.recordings import recorded_input
    from aaria_pin.files.source import open_record

    recorded = recorded_input(request.files[0], request.run)
    if recorded is None:
        if request.imu_model is not None:
            raise ParameterError(
                f"imu_model is {request.imu_model} for a simulated run; allowed: with a "
                "recording (a simulated run holds the noise it was made with)",
                parameter="imu_model",
                value=request.imu_model,
            )
        signals = ArmSignals.of_record(open_record(request.files[0], request.run))
    else:
        signals = ArmSignals.of_recorded(
            recorded, _noise_parameters(request.imu_model), str(request.imu_model)
        )
    start = None if request.start is None else _start_table(request.start)
    result = identify_kinematics(signals, progress=request.progress, start=start)
    if result.failure is None:
        _write_kinematics(result, request)
    report, lines = result.to_json(), result.summary()
    if recorded is not None:  # a recording holds no noise model and no truth: say what was assumed
        report["noise_model"], report["resampled"] = signals.noise_model, list(signals.notes)
        lines = [f"noise model: {signals.noise_model}", *signals.notes, *lines]
    return IdentifyOutcome(report, tuple(lines), failure=result.failure)


def identify_files(request: IdentifyRequest) -> IdentifyOutcome:
    """Identify what the request asks, write its outputs, and return the report and its text.

    Args:
        request: the mode, the files and the outputs

    Returns:
        The report and its text lines; a failed kinematic fit writes nothing and says why
        (:attr:`IdentifyOutcome.failure`; the CLI exits 1).

    Raises:
        ParameterError: ``run`` missing for a data set or given for a run file, a holdout
            outside [0, 0.9], a record the identification cannot take.
        InputFileError: an unreadable file, a run whose model cannot be rebuilt.
        OutputFileError: an output of another type, or one that cannot be written.
    """
    if request.bodies:
        return _bodies(request)
    kinematics = not (request.dynamics or request.dataset)
    if kinematics:
        _check_output(request.output, "output", "CSV table", ".csv")
        _check_output(request.urdf, "urdf", "URDF", ".urdf")
    else:
        _check_output(request.output, "output", "JSON report", ".json")
        _check_output(request.dynamics_urdf, "dynamics_urdf", "URDF", ".urdf")
    if request.dataset:
        return _benchmark(request)
    if kinematics:
        return _kinematics(request)
    from aaria_pin.files.source import open_record

    record = open_record(request.files[0], request.run)
    from aaria_pin.apps.identify.inertial import identify_dynamics
    from aaria_pin.apps.identify.inertial_result import dynamics_summary
    from aaria_pin.apps.identify.inertial_torques import TorqueSource

    holdout = DEFAULT_HOLDOUT if request.holdout is None else request.holdout
    fit = identify_dynamics(
        record,
        holdout=holdout,
        torques=TorqueSource(request.torques, request.torque_constant, request.gear_ratio),
        friction=request.friction,
        consistent=request.consistent or request.dynamics_urdf is not None,
    )
    report = fit.to_json()
    _write_json(request.output, report)
    if request.dynamics_urdf is not None:
        from aaria_pin.apps.identify.inertial_urdf import identified_urdf
        from aaria_pin.files.io import write_text_atomic

        write_text_atomic(request.dynamics_urdf, identified_urdf(record, fit))
    lines = dynamics_summary(report, request.parameters)
    if request.dynamics_urdf is not None:
        lines.append(f"wrote {request.dynamics_urdf}: the run's URDF with the fitted dynamics")
    return IdentifyOutcome(report, tuple(lines))
