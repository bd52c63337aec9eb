"""The front door's errors are ours: a wrong argument to a public name raises an AariaError.

Every function and input class of the front door (``aaria_pin.__all__`` and the packages that
export names lazily, ``aaria_pin.apps.dataset`` and ``aaria_pin.apps.wrist``) is called with a
good call's arguments and one of them replaced by a bad one, derived from the text of its
annotation (so a new public function is covered as soon as it is exported):

- a wrong TYPE (``None`` where the parameter is not optional, text where a number, an array or an
  object is expected, an integer where text, a path or an object is, ``True`` where a number is,
  ``object()`` anywhere): a :class:`~aaria_pin.errors.ParameterTypeError`, which is a
  ``ParameterError`` and a ``TypeError``;
- a bad VALUE of the right type (a NaN number, a NaN array, an array of the wrong shape, an
  integer where an array is): an AariaError that is not a ``TypeError``.

Either way the error names the parameter (``parameter``) and its message is one line; no raw
``TypeError``, ``AttributeError``, NumPy or h5py error escapes. Keyword options typed by a
``TypedDict`` (``**options: Unpack[...]``) are parameters too. The classes the library makes
for its results (a run record, a model) are not inputs and are left out (:data:`RESULTS`).
"""

from __future__ import annotations

import importlib
import inspect
import math
import typing
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import aaria_pin
from aaria_pin.errors import AariaError, ParameterError, ParameterTypeError

PACKAGES = ("aaria_pin", "aaria_pin.apps.dataset", "aaria_pin.apps.wrist")
"""The front door and the packages that export names of their modules."""

RESULTS = {
    "Angles",
    "ColumnView",
    "DHRobot",
    "DatasetReport",
    "KinematicChain",
    "Preset",
    "RecordedRun",
    "RobotDescription",
    "RobotModel",
    "RunRecord",
    "UrdfRobot",
    "WindowDataset",
    "WristSolutions",
}
"""Classes of results the library makes (by :func:`build_dh_robot`, :func:`simulate`, a reader's
``windows``, :func:`import_recordings`, ...); the functions that make them are checked."""

ALIASES = {
    "Convention": "str",
    "JointValue": "float | Sequence[float]",
    "BalanceInertia": "bool | str",
    "MotionInput": "Motion | None",
    "Seeds": "RunSeeds | int | SeedSequence",
}
"""Type aliases of the signatures, as the kinds they stand for."""

TYPE, VALUE = "type", "value"

CHECKED_WHEN_USED = {
    ("DHArmSpec", "joint_table"),
    ("DHArmSpec", "base_table"),
    ("DHArmSpec", "imu_mount"),
    ("UrdfRunSpec", "joint_table"),
    ("UrdfRunSpec", "base_table"),
    ("TorqueDrive", "torques"),
    ("ImuMount", "T_parent_imu"),
    ("dh_request", "torques"),
    ("urdf_request", "torques"),
    ("fourier_motion", "qd_limits"),
    ("fourier_motion", "qdd_limits"),
}
"""Arrays whose VALUES a spec or request keeps unchecked until a run uses it (their types are
checked when given): a NaN or a wrong shape is refused by the run, naming the table."""

VALUE_NAMES = {
    "dh_table": "table",
    "joint_table": "table",
    "base_table": "table",
    "rotation": "matrix",
}
"""The parameter a shared validator names for a bad VALUE of a table (the DH and oscillation
table checks name ``table``, the rotation check ``matrix``)."""


def _front_door() -> dict[str, Callable[..., Any]]:
    names: dict[str, Callable[..., Any]] = {}
    for package in PACKAGES:
        module = importlib.import_module(package)
        for name in module.__all__:
            value = getattr(module, name)
            is_error = inspect.isclass(value) and issubclass(value, BaseException)
            made = name in RESULTS or inspect.isabstract(value)  # DatasetSpec: of its kinds
            if callable(value) and not is_error and not made:
                names.setdefault(name, value)
    return names


FRONT_DOOR = _front_door()


def _parts(text: str) -> set[str]:
    """The members of an annotation's top-level union, aliases expanded."""
    parts, depth, start = set(), 0, 0
    for index, char in enumerate(text + "|"):
        depth += 1 if char in "[(" else -1 if char in "])" else 0
        if char == "|" and depth == 0:
            part = text[start:index].strip()
            parts |= _parts(ALIASES[part]) if part in ALIASES else {part}
            start = index + 1
    return parts


def _kinds(text: str) -> set[str]:
    kinds = set()
    for part in _parts(text):
        head = part.split("[")[0].split(".")[-1]
        if head == "Literal" and part.split("[", 1)[1][:1] in "\"'":
            kinds.add("text")  # Literal["a", "b"]: a str; a wrong one is a bad VALUE
            continue
        kinds.add(
            {
                "None": "none",
                "ArrayLike": "array",
                "Array": "array",
                "float": "number",
                "int": "integer",
                "bool": "bool",
                "str": "text",
                "PathLike": "path",
                "Path": "path",
                "Any": "any",
                "Callable": "callable",
            }.get(head, "object")
        )
    return kinds


@dataclass(frozen=True)
class Case:
    """One bad call: ``name`` given ``bad`` (made by ``make``) must raise a ``kind`` error."""

    function: str
    parameter: str
    bad: str
    kind: str

    @property
    def id(self) -> str:
        return f"{self.function}-{self.parameter}-{self.bad}"


BAD_VALUES: dict[str, Callable[[Any], Any]] = {
    "None": lambda good: None,
    "text": lambda good: "1",
    "int": lambda good: 7,
    "True": lambda good: True,
    "object": lambda good: object(),
    "nan": lambda good: math.nan,
    "nan-array": lambda good: np.full(np.shape(good) if np.ndim(good) else (2, 4), np.nan),
    "shape": lambda good: np.zeros((3, 5, 2)),
}


def _cases_of(kinds: set[str]) -> Iterator[tuple[str, str]]:
    if "any" in kinds:
        return
    numeric = kinds & {"number", "integer"}
    if "none" not in kinds:
        yield "None", TYPE
    if not kinds & {"text", "path"}:
        yield "text", TYPE
    if not numeric and "bool" not in kinds:
        yield "int", VALUE if "array" in kinds else TYPE
    if numeric and "bool" not in kinds:
        yield "True", TYPE
    yield "object", TYPE
    if "number" in kinds:
        yield "nan", VALUE
    if "array" in kinds:
        yield "nan-array", VALUE
        yield "shape", VALUE


def parameters(function: Callable[..., Any]) -> dict[str, str]:
    """Each parameter of a public function or class (keyword options included) → its annotation."""
    found: dict[str, str] = {}
    for parameter in inspect.signature(function).parameters.values():
        text = str(parameter.annotation)
        if parameter.kind is inspect.Parameter.VAR_KEYWORD and text.startswith("Unpack["):
            hints = typing.get_type_hints(function)
            (options,) = typing.get_args(hints[parameter.name])
            for key, value in options.__annotations__.items():
                found[key] = getattr(value, "__forward_arg__", str(value))
        elif parameter.kind not in (parameter.VAR_KEYWORD, parameter.VAR_POSITIONAL):
            found[parameter.name] = text
    return found


CASES = [
    Case(name, parameter, bad, kind)
    for name, function in sorted(FRONT_DOOR.items())
    for parameter, text in parameters(function).items()
    for bad, kind in _cases_of(_kinds(text))
]


class Valid:
    """Good arguments, made once: the robots, records and files the calls need."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder

    @property
    def preset(self) -> Any:
        return aaria_pin.get_preset("aaria-fig2")

    @property
    @cache  # noqa: B019 - one Valid per session
    def record(self) -> Any:
        settings = aaria_pin.RunSettings(duration=1.0, rate=100.0)
        return aaria_pin.simulate(aaria_pin.preset_arm("aaria-fig2"), settings=settings)

    @property
    @cache  # noqa: B019
    def run_file(self) -> Path:
        return aaria_pin.write_run(self.folder / "run.h5", self.record)

    @property
    @cache  # noqa: B019
    def table_file(self) -> Path:
        path = self.folder / "table.csv"
        np.savetxt(path, np.asarray(self.preset.table), delimiter=",")
        return path

    @property
    @cache  # noqa: B019
    def recorded(self) -> Any:
        return aaria_pin.open_recorded(self.run_file)

    @property
    @cache  # noqa: B019
    def recording(self) -> Path:
        return aaria_pin.export_run(self.record, self.folder / "recording.csv")

    @property
    @cache  # noqa: B019
    def consistent(self) -> Any:
        return aaria_pin.identify_dynamics(self.record, consistent=True)

    @property
    @cache  # noqa: B019
    def spec(self) -> Any:
        sources = aaria_pin.DatasetSources(n_runs=2, duration=0.2, preset="aaria-fig2")
        return sources.spec()

    @property
    @cache  # noqa: B019
    def dataset_file(self) -> Path:
        path = self.folder / "dataset.h5"
        aaria_pin.generate_dataset(path, self.spec, workers=1)
        return path

    @property
    @cache  # noqa: B019
    def urdf(self) -> str:
        return aaria_pin.find_robot("ur5").urdf.read_text(encoding="utf-8")

    @property
    @cache  # noqa: B019
    def loaded(self) -> Any:
        return aaria_pin.load_urdf_robot(self.urdf)

    @property
    @cache  # noqa: B019
    def xml(self) -> str:
        return str(aaria_pin.record_mjcf(self.record)[0])

    def new_path(self, suffix: str) -> Path:
        count = len(list(self.folder.glob(f"new*{suffix}")))
        return self.folder / f"new{count}{suffix}"

    def call(self, name: str) -> dict[str, Any]:
        """The keyword arguments of a good call of ``name`` (its required ones, and a short run)."""
        table = self.preset.table
        short = aaria_pin.RunSettings(duration=0.2, rate=100.0)
        samples = aaria_pin.trajectory_from_samples(
            np.linspace(0.0, 0.2, 21), np.zeros((21, 3)), rate=100.0
        )
        calls: dict[str, Callable[[], dict[str, Any]]] = {
            "DatasetReader": lambda: {"path": self.dataset_file},
            "DatasetSettings": lambda: {"n_runs": 2},
            "DatasetSources": lambda: {"n_runs": 2},
            "DatasetSpec": lambda: {"n_runs": 2},
            "FourierMotion": lambda: {
                "excitation": aaria_pin.dh_fourier_excitation(table, 0.2, 100.0)
            },
            "ImuMount": lambda: {"name": "imu_x", "parent": "link1", "T_parent_imu": np.eye(4)},
            "RunRequest": lambda: {"robot": aaria_pin.preset_arm("aaria-fig2")},
            "RunSeeds": lambda: {"seed": 3},
            "SampledTrajectory": lambda: {"samples": samples},
            "TorqueDrive": lambda: {"torques": np.zeros((21, 8))},
            "angles_from_matrix": lambda: {"matrix": np.eye(3), "seq": "xyz"},
            "build_dh_robot": lambda: {"table": table},
            "build_model": lambda: {"urdf": self.urdf, "tool_frame": "tool0"},
            "chain_from_table": lambda: {"table": table},
            "dh_arm": lambda: {"dh_table": table},
            "dh_fourier_excitation": lambda: {"dh_table": table, "duration": 0.2},
            "dh_request": lambda: {"dh_table": table, "duration": 0.2},
            "emit_urdf": lambda: {"description": aaria_pin.build_dh_robot(table).description},
            "export_run": lambda: {"record": self.record, "path": self.new_path(".csv")},
            "find_robot": lambda: {"name": "ur5"},
            "fourier_motion": lambda: {"n_joints": 3, "duration": 0.2, "rate": 100.0},
            "generate_dataset": lambda: {"path": self.new_path(".h5"), "spec": self.spec},
            "get_preset": lambda: {"name": "aaria-fig2"},
            "identified_urdf": lambda: {"record": self.record, "result": self.consistent},
            "identify_joint": lambda: {
                "source": self.recorded,
                "imu_a": "imu_link1_a",
                "imu_b": "imu_link2_a",
            },
            "identify_rigid": lambda: {
                "source": self.recorded,
                "imu_a": "imu_link2_a",
                "imu_b": "imu_link2_b",
            },
            "identify_dynamics": lambda: {"record": self.record},
            "identify_kinematics": lambda: {
                "record": self.record,
                "max_iterations": 1,
                "max_fit_samples": 20,
            },
            "import_recordings": lambda: {"paths": [self.recording]},
            "load_urdf_robot": lambda: {"urdf": self.urdf},
            "matrix_from_angles": lambda: {"angles": [0.1, 0.2, 0.3], "seq": "xyz"},
            "open_record": lambda: {"path": self.run_file},
            "open_recorded": lambda: {"path": self.run_file},
            "preset_arm": lambda: {"name": "aaria-fig2"},
            "read_run": lambda: {"path": self.run_file},
            "read_run_inputs": lambda: {"path": self.run_file},
            "read_table": lambda: {"path": self.table_file},
            "record_mjcf": lambda: {"record": self.record},
            "replay_in_mujoco": lambda: {"record": self.record, "xml": self.xml},
            "simulate": lambda: {"robot": aaria_pin.preset_arm("aaria-fig2"), "settings": short},
            "simulate_pieces": lambda: {
                "robot": aaria_pin.preset_arm("aaria-fig2"),
                "settings": short,
            },
            "trajectory_from_samples": lambda: {
                "time": np.linspace(0.0, 0.2, 21),
                "q": np.zeros((21, 3)),
                "rate": 100.0,
            },
            "urdf_fourier_excitation": lambda: {"loaded": self.loaded, "duration": 0.2},
            "urdf_request": lambda: {"urdf": self.urdf, "duration": 0.2},
            "urdf_robot_run": lambda: {"loaded": self.loaded},
            "wrist_fk": lambda: {"joints": [0.1, 0.5, -0.2]},
            "wrist_ik": lambda: {"rotation": np.eye(3)},
            "write_run": lambda: {"path": self.new_path(".h5"), "record": self.record},
        }
        return calls[name]() if name in calls else {}

    def good(self, name: str, parameter: str) -> Any:
        """A good value of an array parameter (its shape is the NaN array's)."""
        arrays = {
            "dh_table": self.preset.table,
            "table": self.preset.table,
            "joint_table": self.preset.joint_table,
            "base_table": self.preset.base_table,
            "imu_mount": np.tile(np.eye(4), (14, 1, 1)),
        }
        return self.call(name).get(parameter, arrays.get(parameter))


def run(function: Callable[..., Any], arguments: dict[str, Any]) -> Any:
    result = function(**arguments)
    return list(result) if inspect.isgenerator(result) else result


@pytest.fixture(scope="module")
def valid(tmp_path_factory: pytest.TempPathFactory) -> Valid:
    return Valid(tmp_path_factory.mktemp("front_door"))


def test_the_cases_cover_every_public_function_and_input_class() -> None:
    """Derived from the signatures: each of them, and each kind of bad argument, is tried."""
    covered = {case.function for case in CASES}
    assert covered == set(FRONT_DOOR) - {"SineTable"}  # SineTable() takes no argument
    assert {"simulate", "dh_request", "record_mjcf", "RunSettings"} <= covered
    assert {case.bad for case in CASES} == set(BAD_VALUES)
    assert len(CASES) > 300
    by_call = {(case.function, case.parameter, case.bad): case.kind for case in CASES}
    assert by_call[("dh_request", "duration", "text")] == TYPE  # a keyword option
    assert by_call[("record_mjcf", "record", "None")] == TYPE
    assert by_call[("wrist_fk", "joints", "nan-array")] == VALUE
    assert ("open_record", "run", "None") not in by_call  # optional


@pytest.mark.parametrize("name", sorted(FRONT_DOOR))
def test_the_good_calls_succeed(name: str, valid: Valid) -> None:
    """The good call each bad call starts from is good (so a bad call's error is its own)."""
    result = run(FRONT_DOOR[name], valid.call(name))
    assert result is not None


@pytest.mark.parametrize("case", CASES, ids=[case.id for case in CASES])
def test_a_bad_argument_raises_our_error_naming_it(case: Case, valid: Valid) -> None:
    arguments = valid.call(case.function)
    arguments[case.parameter] = BAD_VALUES[case.bad](valid.good(case.function, case.parameter))
    if case.kind == VALUE and (case.function, case.parameter) in CHECKED_WHEN_USED:
        try:
            run(FRONT_DOOR[case.function], arguments)
        except AariaError as error:  # refused at once: as any other
            assert not isinstance(error, TypeError) and "\n" not in str(error)
        return
    with pytest.raises(AariaError) as caught:
        run(FRONT_DOOR[case.function], arguments)
    error = caught.value
    named = {case.parameter, VALUE_NAMES.get(case.parameter) if case.kind == VALUE else None}
    assert error.parameter in named, str(error)
    assert "\n" not in str(error) and str(error)
    if case.kind == TYPE:
        assert isinstance(error, ParameterTypeError)
        assert isinstance(error, ParameterError) and isinstance(error, TypeError)
    else:
        assert not isinstance(error, TypeError), str(error)
