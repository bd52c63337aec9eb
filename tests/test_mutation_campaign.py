"""The adversarial campaign of issue 28: damaged real files through every reading command.

Real files are made once by the tool itself (a 0.2 s DH run as ``.h5`` and ``.mat``, a ur5 run,
a wrist run, a 3-run data set). For each file × mutator (``tests/mutations.py``: truncate,
invert bytes in an array's stored data, delete an array, store one with another shape or type,
retype an attribute, a bogus ``kind``, broken JSON, ``N`` < 0, NaN or inf in a series),
hypothesis draws the offsets, arrays and attributes; the damaged copy then goes through every
command that reads it, in process (click's runner on ``aaria_pin.cli.main``). The invariant,
per command:

- either it succeeds exactly as on the intact file (exit 0, the same stdout and output file
  contents: the damage lies in a region that command does not read),
- or it refuses the file: exit 2, exactly one stderr line starting ``aaria: error:``, no
  traceback (the exception is click's SystemExit), nothing written. ``check`` may also exit 1
  (damage found), listing the damage on stdout.

The Python readers (``read_run``, ``DatasetReader.record``) get the same damage, on these files
and on the 0.1/0.2/0.3 fixtures: each run reads as intact or raises a one-line InputFileError.
``aaria check`` must find every damaged run. A few cases run in a process of their own, to
catch a crash of the C libraries (a negative return code: SIGSEGV, SIGABRT). ``pytest -s``
prints the counts: files, mutations, invocations.
The number of examples per file × mutator is ``AARIA_CAMPAIGN_EXAMPLES`` (default 6), drawn
from a fixed seed so that the suite is repeatable; raise it (and unset the seed with
``AARIA_CAMPAIGN_RANDOM=1``) for a deeper search.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from collections import Counter
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from tests.mutations import MUTATORS, SERIES, damage_chunk, damage_run, invoke_in

EXAMPLES = int(os.environ.get("AARIA_CAMPAIGN_EXAMPLES", "6"))
"""Mutated copies per file × mutator."""

CAMPAIGN = settings(
    max_examples=EXAMPLES,
    deadline=None,
    database=None,
    derandomize=not os.environ.get("AARIA_CAMPAIGN_RANDOM"),
    phases=[Phase.explicit, Phase.generate],  # no shrinking: each example runs ~10 commands
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)

FILES = {"dh.h5": "h5", "dh.mat": "mat", "ur5.h5": "h5", "wrist.h5": "h5", "ds.h5": "dataset"}
"""The real files of the campaign and their format (the key of ``MUTATORS``)."""

MAKE = {
    "dh.h5": "simulate --preset aaria-fig2 --duration 0.2 --rate 100 -o dh.h5",
    "dh.mat": "simulate --preset aaria-fig2 --duration 0.2 --rate 100 -o dh.mat",
    "ur5.h5": "simulate --robot ur5 --duration 0.2 --rate 100 -o ur5.h5",
    "wrist.h5": "wrist simulate 60 45 -30 --duration 0.2 -o wrist.h5",
    "ds.h5": "dataset -n 3 --duration 0.2 --rate 100 --workers 1 -o ds.h5",
}
"""How each file is made: the tool's own commands."""

COUNTS: Counter[str] = Counter()
"""What the campaign ran: files, mutations, invocations (printed at the end of the module)."""


def _commands(name: str, run: int) -> list[list[str]]:
    """Every reading command over file ``name`` (``run``: the run of a data set)."""
    pick = ["--run", str(run)] if FILES[name] == "dataset" else []
    commands = [
        ["torques", name, *pick],
        ["plot", name, *pick, "--imu", "imu_base", "--width", "400", "-o", "x.png"],
        ["identify", "--dynamics", name, *pick],
        ["dataset-stats", name],
        ["simulate", "--from", name, "-o", "y.h5"],
        ["mjcf", "--from", name, "-o", "m.xml"],
        ["view", name, *pick, "-o", "v.html"],
    ]
    commands.append(["check", name])
    return commands


def _contents(folder: Path, leave: frozenset[str] | set[str] = frozenset()) -> dict[str, Any]:
    """The files of ``folder`` by name, but those in ``leave``: an HDF5 file by its attributes
    and arrays (HDF5 keeps a time stamp in its headers), any other file by its bytes."""
    import h5py

    found: dict[str, Any] = {}
    for path in sorted(folder.iterdir()):
        if path.name in leave:
            continue
        found[path.name] = path.read_bytes()
        if path.suffix == ".h5" and h5py.is_hdf5(path):
            with h5py.File(path, "r") as handle:
                found[path.name] = (
                    {key: repr(value) for key, value in handle.attrs.items()},
                    {key: repr(item[()]) for key, item in handle.items()},
                )
    return found


def _invoke(
    folder: Path, argv: list[str], keep: bool = False
) -> tuple[int, str, str, Any, dict[str, Any]]:
    """Run ``aaria argv`` in process with ``folder`` as the working folder.

    Returns:
        Exit status, stdout, stderr, the exception click caught, the files written (removed
        again unless ``keep``).
    """
    before = {path.name for path in folder.iterdir()}
    result = invoke_in(folder, argv)
    written = _contents(folder, before)
    for name in written if not keep else ():
        (folder / name).unlink()
    return result.exit_code, result.stdout, result.stderr, result.exception, written


@pytest.fixture(scope="session")
def originals(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The intact files, made by the tool."""
    folder = tmp_path_factory.mktemp("originals")
    for command in MAKE.values():
        status, _, stderr, _, _ = _invoke(folder, command.split(), keep=True)
        assert status == 0, (command, stderr)
    return folder


@pytest.fixture(scope="session")
def intact(originals: Path, tmp_path_factory: pytest.TempPathFactory) -> Any:
    """The result of each command on the intact file (computed once, on first use)."""
    folder = tmp_path_factory.mktemp("intact")
    cache: dict[tuple[str, ...], tuple[int, str, str, Any, dict[str, Any]]] = {}

    def outcome(name: str, argv: list[str]) -> tuple[int, str, str, Any, dict[str, Any]]:
        key = tuple(argv)
        if key not in cache:
            shutil.copyfile(originals / name, folder / name)
            cache[key] = _invoke(folder, argv)
            (folder / name).unlink()
        return cache[key]

    return outcome


@pytest.fixture(scope="module", autouse=True)
def report_counts() -> Iterator[None]:
    yield
    print(
        f"\ncampaign: {len(FILES)} files, {COUNTS['mutations']} mutations "
        f"({COUNTS['kinds']} file x mutator pairs), {COUNTS['invocations']} invocations "
        f"in process, {COUNTS['subprocess']} in a process of their own"
    )


def _problem(
    argv: list[str], got: tuple[int, str, str, Any, dict[str, Any]], intact: tuple[Any, ...]
) -> str | None:
    """Why ``got`` breaks the invariant (None: it holds)."""
    status, stdout, stderr, exception, written = got
    if status == 0 and (status, stdout, written) == (intact[0], intact[1], intact[4]):
        return None  # stderr aside: warnings and notes of a first call
    refused = (1, 2) if argv[0] == "check" else (2,)
    lines = stderr.splitlines()
    if status == 0:
        differ = [
            what
            for what, a, b in (("stdout", stdout, intact[1]), ("output file", written, intact[4]))
            if a != b
        ]
        if intact[0] != 0:
            differ = [f"the intact file exits {intact[0]}"]
        return (
            f"exit 0, but {' and '.join(differ)} differ(s) from the intact file's: {stdout[:160]!r}"
        )
    if status not in refused:
        last = lines[-1] if lines else ""
        return f"exit {status}, allowed {refused}: {type(exception).__name__}: {exception} {last!r}"
    if not isinstance(exception, SystemExit):
        return f"{type(exception).__name__}: {exception}"
    if "Traceback" in stdout + stderr:
        return f"a traceback: {stderr[-300:]!r}"
    if argv[0] == "check" and status == 1:  # damage found: listed on stdout, a run a line
        if not stdout.strip():
            return "check: exit 1 but nothing listed"
    elif len(lines) != 1 or not lines[0].startswith("aaria: error: "):
        return f"stderr is not one 'aaria: error:' line: {stderr[:400]!r}"
    if written:
        return f"wrote {sorted(written)} although it failed"
    return None


def _campaign(
    name: str, mutator: str, data: st.DataObject, originals: Path, intact: Any, work: Path
) -> list[str]:
    """Mutate a copy of ``name`` and run every reading command on it: the broken invariants."""
    target = work / name
    shutil.copyfile(originals / name, target)
    done = MUTATORS[FILES[name]][mutator](target, data.draw)
    COUNTS["mutations"] += 1
    run = data.draw(st.integers(0, 2)) if FILES[name] == "dataset" else 0
    problems = []
    for argv in _commands(name, run):
        got = _invoke(work, argv)
        COUNTS["invocations"] += 1
        why = _problem(argv, got, intact(name, argv))
        if why:
            problems.append(f"aaria {' '.join(argv)}: {why}")
    target.unlink()
    return [f"{name} {done}: {problem}" for problem in problems]


PAIRS = [(name, mutator) for name, kind in FILES.items() for mutator in MUTATORS[kind]]


@pytest.mark.parametrize(("name", "mutator"), PAIRS)
def test_a_damaged_file_is_refused_in_one_line_or_read_as_intact(
    name: str, mutator: str, originals: Path, intact: Any, tmp_path: Path
) -> None:
    COUNTS["kinds"] += 1

    @CAMPAIGN
    @given(data=st.data())
    def campaign(data: st.DataObject) -> None:
        work = tmp_path / f"work{COUNTS['mutations']}"
        work.mkdir()
        problems = _campaign(name, mutator, data, originals, intact, work)
        assert not problems, "\n".join(problems)

    campaign()


def _record_state(record: Any) -> tuple[Any, ...]:
    """A run record as plain, comparable values: its arrays (bytes, or lists for strings)
    and its decoded attributes."""
    arrays = {
        name: (value.shape, value.dtype.str, value.tobytes())
        if value.dtype.kind in "biuf"
        else repr(value.tolist())
        for name, value in record.arrays().items()
    }
    return arrays, repr(record.attributes)


def _read(path: Path, fmt: str) -> list[Any]:
    """What the Python readers give for ``path``: per run, its state or the error raised."""
    from aaria_pin import DatasetReader, read_run
    from aaria_pin.errors import InputFileError

    def attempt(read: Any, *args: Any) -> Any:
        try:
            return _record_state(read(*args))
        except InputFileError as error:
            return error

    if fmt != "dataset":
        return [attempt(read_run, path)]
    try:
        reader = DatasetReader(path)
    except InputFileError as error:
        return [error]
    with reader:
        return [attempt(reader.record, run) for run in range(len(reader.complete))]


def _read_damaged(source: Path, fmt: str, mutator: str, work: Path) -> None:
    """Damage copies of ``source`` with ``mutator`` (hypothesis drawing); assert that the
    Python readers give each run as they give the intact file's, or refuse it with a one-line
    InputFileError naming the file argument."""
    intact = _read(source, fmt)

    @settings(CAMPAIGN, max_examples=2 * EXAMPLES)
    @given(data=st.data())
    def case(data: st.DataObject) -> None:
        folder = work / f"py{COUNTS['mutations']}"
        folder.mkdir()
        shutil.copyfile(source, folder / source.name)
        done = MUTATORS[fmt][mutator](folder / source.name, data.draw)
        COUNTS["mutations"] += 1
        got = _read(folder / source.name, fmt)
        whole_file_refused = len(got) == 1 and isinstance(got[0], Exception)
        assert whole_file_refused or len(got) == len(intact), (done, len(got), len(intact))
        for run, (state, before) in enumerate(zip(got, intact, strict=False)):
            if isinstance(state, Exception):
                assert len(str(state).splitlines()) == 1, (done, run, str(state))
                assert getattr(state, "parameter", None) == "file", (done, run, state)
            elif state != before:
                arrays, attributes = state
                names = set(arrays) | set(before[0])
                differ = sorted(k for k in names if arrays.get(k) != before[0].get(k))
                differ += ["attributes"] if attributes != before[1] else []
                raise AssertionError(f"{done}: run {run} is read with other {differ}")

    case()


@pytest.mark.parametrize(("name", "mutator"), PAIRS)
def test_the_python_readers_refuse_a_damaged_file_or_read_it_as_intact(
    name: str, mutator: str, originals: Path, tmp_path: Path
) -> None:
    """``read_run`` and ``DatasetReader.record`` on a damaged copy: each run reads exactly as
    intact, or raises InputFileError (an OSError) with one line naming the file argument;
    never another exception (KeyError, ValueError, h5py's OSError, zlib.error...)."""
    _read_damaged(originals / name, FILES[name], mutator, tmp_path)


FIXTURES = Path(__file__).parent / "fixtures"
LEGACY = {
    "v0_1_0/dh_run.h5": "h5",
    "v0_1_0/dh_run.mat": "mat",
    "v0_1_0/dh_dataset.h5": "dataset",
    "v0_2_0/dh_run.h5": "h5",
    "v0_3_0/dh_dataset.h5": "dataset",
}
"""Files of earlier versions (no checksums in their run files: inverted bytes are left out)."""
LEGACY_MUTATORS = ("truncate", "delete_array", "attribute_type", "broken_json", "nonfinite")


@pytest.mark.parametrize("mutator", LEGACY_MUTATORS)
@pytest.mark.parametrize("name", sorted(LEGACY))
def test_the_python_readers_refuse_a_damaged_old_file_or_read_it_as_intact(
    name: str, mutator: str, tmp_path: Path
) -> None:
    """Old files keep reading, and damage to them is refused as in new files."""
    _read_damaged(FIXTURES / name, LEGACY[name], mutator, tmp_path)


# --- the issue's own cases, by name -------------------------------------------------------


def _one_line_exit_2(folder: Path, argv: list[str]) -> str:
    """Assert that ``aaria argv`` refuses in one line, writing nothing; return that line."""
    status, _, stderr, exception, written = _invoke(folder, argv)
    COUNTS["invocations"] += 1
    assert status == 2, (argv, status, stderr, exception)
    assert isinstance(exception, SystemExit), exception
    lines = stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("aaria: error: "), stderr
    assert not written, sorted(written)
    return lines[0]


def test_a_damaged_chunk_names_the_run(originals: Path, tmp_path: Path) -> None:
    """The issue's first traceback: bytes overwritten inside run 1's ``tau`` of a data set."""
    shutil.copyfile(originals / "ds.h5", tmp_path / "ds.h5")
    damage_chunk(tmp_path / "ds.h5", "tau", 1)
    for argv in (
        ["torques", "ds.h5", "--run", "1"],
        ["view", "ds.h5", "--run", "1", "-o", "v.html"],
        ["render", "--from", "ds.h5", "--run", "1", "-o", "r.png"],
        ["identify", "--dynamics", "ds.h5", "--run", "1"],
        ["dataset-stats", "ds.h5", "--split", "all", "--names", "tau"],
    ):
        line = _one_line_exit_2(tmp_path, argv)
        assert "run 1" in line and "damaged" in line, line


def test_nan_in_the_imu_signals_is_refused_before_identification(
    originals: Path, tmp_path: Path
) -> None:
    """NaN in ``imu`` made ``identify`` fail inside numpy ("SVD did not converge"): now one
    line naming the array (as NaN, or as damaged: its checksum no longer matches)."""
    import h5py

    shutil.copyfile(originals / "dh.h5", tmp_path / "dh.h5")
    with h5py.File(tmp_path / "dh.h5", "r+") as handle:
        handle["imu"][5, 3, 2] = np.nan
    line = _one_line_exit_2(tmp_path, ["identify", "dh.h5"])
    assert "imu" in line and ("nan" in line.lower() or "damaged" in line), line


def test_check_finds_every_damaged_run(originals: Path, tmp_path: Path) -> None:
    """``aaria check`` verifies the checksums of a whole data set: exit 1, the run named."""

    @CAMPAIGN
    @given(data=st.data())
    def case(data: st.DataObject) -> None:
        work = tmp_path / f"work{COUNTS['mutations']}"
        work.mkdir()
        shutil.copyfile(originals / "ds.h5", work / "ds.h5")
        run, done = damage_run(work / "ds.h5", data.draw)
        COUNTS["mutations"] += 1
        status, stdout, stderr, exception, written = _invoke(work, ["check", "ds.h5"])
        COUNTS["invocations"] += 1
        assert status == 1, (done, status, stdout, stderr, exception)
        assert f"run {run}" in stdout + stderr, (done, stdout, stderr)
        assert "Traceback" not in stdout + stderr and not written, (done, stderr)

    case()


def _runs(path: Path) -> dict[str, bytes]:
    """Every per-run array of a data set, as bytes."""
    import h5py

    with h5py.File(path, "r") as handle:
        return {name: np.asarray(handle[name]).tobytes() for name in SERIES}


def test_resume_remakes_every_damaged_run(originals: Path, tmp_path: Path) -> None:
    """``dataset --resume`` over a complete data set verifies it and re-makes a damaged run:
    afterwards every run's series are the intact file's, bit for bit."""
    expected = _runs(originals / "ds.h5")

    @CAMPAIGN
    @given(data=st.data())
    def case(data: st.DataObject) -> None:
        work = tmp_path / f"resume{COUNTS['mutations']}"
        work.mkdir()
        shutil.copyfile(originals / "ds.h5", work / "ds.h5")
        _, done = damage_run(work / "ds.h5", data.draw)
        COUNTS["mutations"] += 1
        status, _, stderr, exception, _ = _invoke(work, [*MAKE["ds.h5"].split(), "--resume"])
        COUNTS["invocations"] += 1
        assert status == 0, (done, status, stderr, exception)
        got = _runs(work / "ds.h5")
        assert got == expected, (done, sorted(k for k in got if got[k] != expected[k]))

    case()


def test_check_finds_damage_in_a_run_file(originals: Path, tmp_path: Path) -> None:
    """Run files carry checksums: ``aaria check`` finds inverted bytes in any of their arrays."""

    @CAMPAIGN
    @given(data=st.data(), name=st.sampled_from(["dh.h5", "ur5.h5", "wrist.h5"]))
    def case(data: st.DataObject, name: str) -> None:
        work = tmp_path / f"work{COUNTS['mutations']}"
        work.mkdir()
        shutil.copyfile(originals / name, work / name)
        done = MUTATORS["h5"]["flip_bytes"](work / name, data.draw)
        COUNTS["mutations"] += 1
        status, stdout, stderr, exception, written = _invoke(work, ["check", name])
        COUNTS["invocations"] += 1
        assert status == 1, (done, status, stdout, stderr, exception)
        assert "Traceback" not in stdout + stderr and not written, (done, stderr)

    case()


SUBPROCESS_CASES = [
    ("ds.h5", "flip_bytes", ["torques", "ds.h5", "--run", "0"]),
    ("ds.h5", "truncate", ["dataset-stats", "ds.h5"]),
    ("dh.h5", "truncate", ["simulate", "--from", "dh.h5", "-o", "y.h5"]),
    ("dh.h5", "flip_bytes", ["plot", "dh.h5", "--imu", "imu_base", "-o", "x.png"]),
    ("dh.mat", "flip_bytes", ["view", "dh.mat", "-o", "v.html"]),
    ("ur5.h5", "delete_array", ["mjcf", "--from", "ur5.h5", "-o", "m.xml"]),
]


@pytest.mark.parametrize(("name", "mutator", "argv"), SUBPROCESS_CASES)
def test_no_crash_in_a_process_of_its_own(
    name: str, mutator: str, argv: list[str], originals: Path, intact: Any, tmp_path: Path
) -> None:
    """HDF5 and zlib run in C: a damaged file must not crash the process (a negative status)."""

    @settings(CAMPAIGN, max_examples=1)
    @given(data=st.data())
    def case(data: st.DataObject) -> None:
        work = tmp_path / f"work{COUNTS['subprocess']}"
        work.mkdir()
        shutil.copyfile(originals / name, work / name)
        done = MUTATORS[FILES[name]][mutator](work / name, data.draw)
        COUNTS["mutations"] += 1
        COUNTS["subprocess"] += 1
        finished = subprocess.run(
            [sys.executable, "-m", "aaria_pin.cli", *argv],
            capture_output=True,
            text=True,
            timeout=300,
            cwd=work,
        )
        assert finished.returncode >= 0, (done, finished.returncode, finished.stderr[-500:])
        got = (
            finished.returncode,
            finished.stdout,
            finished.stderr,
            SystemExit(finished.returncode),
            _contents(work, {name}),
        )
        why = _problem(argv, got, intact(name, argv))
        assert why is None, f"{done}: {why}"

    case()
