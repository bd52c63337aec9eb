"""Issue 28's bad invocations: each exits 2 with one line that names the flag(s), writes nothing.

These are the cases the issue's campaign found silently accepted or ending in a traceback:
options given without the mode they belong to, options that contradict each other, a value
ignored (``--names ''``), tables that are not numbers, an IMU mount from another robot, a rate
above the bound every other command keeps, over-long folder names, click's usage errors at the
top level, and ``identify --dataset`` over a data set with no complete run. The cases of
``tests/cli/test_bad_input.py`` are not repeated here.

Inputs are real files made by the tool (``{name}`` in an argv), in a module-scoped folder; each
case runs in process (click's runner) in a fresh working folder, whose files (and the inputs')
must be unchanged afterwards.
"""

from __future__ import annotations

import re
import shlex
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from tests.mutations import invoke_in

LONG = "d" * 300
"""A folder name longer than any file system takes (255 bytes)."""


def _run(folder: Path, argv: list[str]) -> tuple[int, str, str, BaseException | None]:
    result = invoke_in(folder, argv)
    return result.exit_code, result.stdout, result.stderr, result.exception


@pytest.fixture(scope="module")
def inputs(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A DH run, a ur5 run, a 2-run data set, one with no complete run, and bad tables."""
    import h5py

    folder = tmp_path_factory.mktemp("inputs")
    for command in (
        "simulate --preset aaria-fig2 --duration 0.2 --rate 100 -o dh.h5",
        "simulate --robot ur5 --duration 0.2 --rate 100 -o ur5.h5",
        "dataset -n 2 --duration 0.2 --rate 100 --workers 1 -o ds.h5",
        "dataset -n 2 --duration 0.2 --rate 100 --workers 1 -o none_complete.h5",
    ):
        status, _, stderr, _ = _run(folder, command.split())
        assert status == 0, (command, stderr)
    with h5py.File(folder / "none_complete.h5", "r+") as handle:  # as a job killed early
        handle["complete"][...] = 0
    # tables whose numbers, read as numbers, would be valid: only their type is wrong
    np.save(folder / "bool.npy", np.ones((8, 5), dtype=bool))
    np.save(folder / "zeros_bool.npy", np.zeros((8, 5), dtype=bool))
    np.save(folder / "zeros_text.npy", np.zeros((8, 5)).astype(str))
    np.save(folder / "base_text.npy", np.zeros((2, 4)).astype(str))
    np.save(folder / "text.npy", np.ones((8, 5)).astype(str))
    np.save(folder / "bool_tau.npy", np.ones((21, 6), dtype=bool))
    np.savetxt(folder / "tau.csv", np.zeros((21, 6)), delimiter=",")
    return folder


@pytest.fixture
def work(tmp_path: Path) -> Iterator[Path]:
    folder = tmp_path / "work"
    folder.mkdir()
    yield folder


SIM = "simulate --preset aaria-fig2 --duration 0.2"

# argv ({name}: a file of the inputs, {long}: a 300-byte name), a pattern per flag it must name
CASES = [
    # an output option that is required
    ("urdf --preset aaria-fig2", ["-o|--output"]),
    ("mjcf --preset aaria-fig2", ["-o|--output"]),
    # over-long folder names
    ("arm urdf -o {long}", ["bytes|too long"]),
    ("arm urdf -o {long}/arm", ["bytes|too long"]),
    (SIM + " -o {long}/s.h5", ["bytes|too long"]),
    ("urdf --preset aaria-fig2 -o {long}/r.urdf", ["bytes|too long"]),
    ("mjcf --preset aaria-fig2 -o {long}/m.xml", ["bytes|too long"]),
    ("dataset -n 2 --duration 0.2 -o {long}/d.h5", ["bytes|too long"]),
    ("plot {dh.h5} -o {long}/p.png", ["bytes|too long"]),
    ("view {dh.h5} -o {long}/v.html", ["bytes|too long"]),
    ("template dh -o {long}/t.csv", ["bytes|too long"]),
    ("torques {dh.h5} --plot {long}/t.png", ["bytes|too long"]),
    ("identify --dynamics {dh.h5} -o {long}/i.json", ["bytes|too long"]),
    ("render --preset aaria-fig2 -o {long}/r.png", ["bytes|too long"]),
    ("wrist simulate 60 45 -30 --duration 0.2 -o {long}/w.h5", ["bytes|too long"]),
    # click's usage errors at the top level
    ("--frob", ["--frob"]),
    # options without the mode they belong to
    ("identify {dh.h5} --parameters", ["--parameters", "--dynamics"]),
    ("identify {dh.h5} --holdout 0.3", ["--holdout", "--dynamics"]),
    ("identify {dh.h5} --workers 2", ["--workers", "--dataset"]),
    # options that contradict each other
    (
        SIM + " --drive torque --torques {tau.csv} --motion fourier -o s.h5",
        ["--motion", "--drive|--torques"],
    ),
    # a value that selects nothing
    ("dataset-stats {ds.h5} --names ''", ["--names"]),
    # tables that are not numbers (the flag, the table or its file named)
    ("urdf --dh {bool.npy} -o r.urdf", ["--dh|DH table|bool.npy"]),
    ("urdf --dh {text.npy} -o r.urdf", ["--dh|DH table|text.npy"]),
    ("simulate --dh {text.npy} --duration 0.2 -o s.h5", ["--dh|DH table|text.npy"]),
    (
        SIM + " --joints {zeros_bool.npy} -o s.h5",
        ["--joints|joint oscillation table|zeros_bool.npy"],
    ),
    (
        SIM + " --joints {zeros_text.npy} -o s.h5",
        ["--joints|joint oscillation table|zeros_text.npy"],
    ),
    (SIM + " --base {base_text.npy} -o s.h5", ["--base|base oscillation table|base_text.npy"]),
    (SIM + " --drive torque --torques {bool_tau.npy} -o s.h5", ["--torques|bool_tau.npy"]),
    # an IMU mount whose parents are not links of this robot
    (SIM + " --imu-mount {ur5.h5} -o s.h5", ["--imu-mount"]),
    # the rate bound
    ("mjcf --preset aaria-fig2 --rate 1e12 -o m.xml", ["--rate"]),
    # a data set with no complete run to identify
    ("identify --dataset {none_complete.h5}", ["complete"]),
]


def _argv(text: str, inputs: Path) -> list[str]:
    names = {path.name: str(path) for path in inputs.iterdir()} | {"long": LONG}
    return [
        re.sub(r"\{([\w.]+)\}", lambda match: names[match.group(1)], part)
        for part in shlex.split(text)
    ]


def _listing(*folders: Path) -> dict[str, tuple[int, int]]:
    return {
        str(path): (path.stat().st_size, path.stat().st_mtime_ns)
        for folder in folders
        for path in sorted(folder.rglob("*"))
    }


@pytest.mark.parametrize(("text", "flags"), CASES)
def test_a_bad_invocation_names_its_flags_in_one_line(
    text: str, flags: list[str], inputs: Path, work: Path
) -> None:
    before = _listing(work, inputs)
    status, stdout, stderr, exception = _run(work, _argv(text, inputs))
    assert status == 2, (status, stdout[-300:], stderr, exception)
    assert isinstance(exception, SystemExit), exception
    lines = stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("aaria: error: "), stderr
    assert "Traceback" not in stdout + stderr
    for flag in flags:
        assert re.search(flag, lines[0]), (flag, lines[0])
    assert _listing(work, inputs) == before


RATE_COMMANDS = [
    "simulate --preset aaria-fig2 --duration 0.2 --rate {rate} -o s.h5",
    "mjcf --preset aaria-fig2 --rate {rate} -o m.xml",
    "wrist simulate 60 45 -30 --duration 0.2 --rate {rate} -o w.h5",
    "dataset -n 2 --duration 0.2 --rate {rate} -o d.h5",
]


def test_every_command_keeps_one_rate_bound(work: Path) -> None:
    """A rate above the bound is refused by each command with the same allowed range."""
    allowed = set()
    for command in RATE_COMMANDS:
        status, _, stderr, _ = _run(work, shlex.split(command.format(rate="1e12")))
        assert status == 2, (command, stderr)
        assert "--rate" in stderr, stderr
        allowed.add(stderr.split("allowed:")[-1].strip())
    assert len(allowed) == 1, allowed
    assert list(work.iterdir()) == []
