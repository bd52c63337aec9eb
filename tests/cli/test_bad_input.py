"""Bad input over every command: exit 2, one line naming the problem, nothing written.

Each case is ``(argv, pattern)``: the command runs in a fresh working folder (in process,
through click's runner) and must exit with status 2, print exactly one line on stderr, starting
``aaria: error:`` and matching ``pattern`` (a regular expression), raise nothing else (no
traceback) and leave the working folder and the shared inputs as they were (names, sizes and
modification times). Cases that need a process of their own (an input FIFO, which could make a
reader wait forever) run as ``python -m aaria_pin.cli`` with a time limit.

The inputs (``{name}`` in the argv) are made once: a DH run, a two-run data set, tables (good,
NaN, empty), a URDF with a two-number ``<origin xyz>``, TOML configs, a folder.
In-process cases run under an alarm of ``TIME_LIMIT`` seconds: a hang fails the case.
"""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from aaria_pin.cli import main

LONG_NAME = "x" * 300
"""An output name longer than any file system takes (255 bytes)."""


TIME_LIMIT = 60
"""Seconds a bad-input case may take before it counts as a hang (SIGALRM): a guard, not a
speed test (each case takes well under a second)."""


@pytest.fixture(scope="module")
def inputs(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from aaria_pin.aaria.dh_robot import BodyDimensions, build_dh_robot
    from aaria_pin.aaria.presets import get_preset
    from aaria_pin.aaria.simulate import simulate_run
    from aaria_pin.apps.dataset.dh_spec import DhDatasetSpec
    from aaria_pin.apps.dataset.generate import generate_dataset
    from aaria_pin.files.runfile import write_run

    folder = tmp_path_factory.mktemp("inputs")
    fig2 = get_preset("aaria-fig2").table
    write_run(
        folder / "run.h5", simulate_run(get_preset("aaria-fig3").table, duration=1.0, rate=50)
    )
    generate_dataset(folder / "ds.h5", DhDatasetSpec(n_runs=2, seed=1, duration=0.2), workers=1)
    np.savetxt(folder / "table.csv", fig2, delimiter=",")
    nan_table = fig2.copy()
    nan_table[2, 1] = np.nan
    np.savetxt(folder / "nan.csv", nan_table, delimiter=",")
    np.save(folder / "empty.npy", np.zeros((0,)))
    np.savetxt(folder / "short.csv", fig2[:3], delimiter=",")  # a 3-row (wrist-like) table
    (folder / "empty.csv").write_text("# nothing\n")
    urdf = build_dh_robot(fig2, "aaria", BodyDimensions()).urdf
    (folder / "origin.urdf").write_text(urdf.replace('xyz="0.0 0.0 0.0"', 'xyz="0 0"', 1))
    (folder / "adir").mkdir()
    (folder / "not_utf8.toml").write_bytes(b"a = [0.8, 0.9]\n\xff\xfe\n")
    (folder / "long.toml").write_text('a = "long"\n')
    (folder / "huge.toml").write_text("a = [1e300, 1e301]\n")
    return folder


@pytest.fixture
def work(tmp_path: Path, inputs: Path) -> Iterator[Path]:
    """A fresh working folder holding ``existing.h5`` (a copy of the run), as the cwd."""
    folder = tmp_path / "work"
    folder.mkdir()
    (folder / "existing.h5").write_bytes((inputs / "run.h5").read_bytes())
    old = Path.cwd()
    os.chdir(folder)
    try:
        yield folder
    finally:
        os.chdir(old)


def listing(*folders: Path) -> dict[str, tuple[int, int]]:
    """Every file and folder below ``folders``: (size, mtime in ns)."""
    found = {}
    for folder in folders:
        for path in sorted(folder.rglob("*")):
            status = path.stat()
            found[str(path)] = (status.st_size, status.st_mtime_ns)
    return found


# argv (``{name}`` = a file of the inputs, ``{long}`` = a 300-byte name), stderr pattern
CASES = [
    # urdf
    ("urdf --dh {empty.npy} -o r.urdf", "empty"),
    ("urdf --dh {empty.csv} -o r.urdf", "empty|no rows|no numbers"),
    ("urdf --preset nope -o r.urdf", "--preset is 'nope'; allowed: aaria-fig2"),
    ("urdf --dh missing.csv -o r.urdf", "no such file"),
    ("urdf --dh {adir} -o r.urdf", "directory|folder"),
    ("urdf --dh {nan.csv} -o r.urdf", "row 3, column 2.* nan"),
    ("urdf --preset aaria-fig2 --density nan -o r.urdf", "density .*nan"),
    ("urdf --preset aaria-fig2 --density 1e9 -o r.urdf", "density"),
    ("urdf --preset aaria-fig2 -o r.txt", r"allowed: \.urdf, \.xml"),
    ("urdf --preset aaria-fig2 -o -", "not a file path"),
    ("urdf --preset aaria-fig2 -o nodir/r.urdf", "does not exist"),
    ("urdf --preset aaria-fig2 -o {long}.urdf", "bytes"),
    ("urdf --preset aaria-fig2 -o .", "directory|folder"),
    ("urdf -o r.urdf", "exactly one of --preset NAME or --dh FILE"),
    # render
    ("render --preset nope -o p.png", "pick-place-arm"),
    (
        "render --preset aaria-fig2 --elevation nan -o p.png",
        "--elevation is nan; allowed: a finite",
    ),
    ("render --preset aaria-fig2 --azimuth inf -o p.png", "--azimuth is inf; allowed: a finite"),
    ("render --from {run.h5} --time nan -o p.png", "--time is nan"),
    ("render --from {run.h5} --time 99 -o p.png", "outside the run"),
    ("render --preset aaria-fig2 --width 0 -o p.png", "width 0 px"),
    ("render --preset aaria-fig2 --height 99999 -o p.png", "height 99999 px"),
    ("render --preset aaria-fig2 -o p.jpg", r"allowed: \.png, \.pdf, \.svg"),
    ("render --dh {empty.npy} -o p.png", "empty"),
    ("render --from missing.h5 -o p.png", "no such file"),
    ("render --from {table.csv} -o p.png", "not a run file|unknown run file type"),
    ("render --from {run.h5} --run 1 -o p.png", "--run is .*run file"),
    ("render --from {ds.h5} --run 99 -o p.png", "99"),
    ("render --preset aaria-fig2 -o {long}.png", "bytes"),
    # plot
    ("plot {run.h5} --imu nope -o p.png", "IMU 'nope' is not in the run; allowed: imu_base"),
    ("plot {run.h5} --width 10 -o p.png", "width 10 px"),
    ("plot {adir} -o p.png", "directory|folder"),
    ("plot {empty.csv} -o p.png", "not a run file|unknown run file type"),
    ("plot {run.h5} -o p.gif", r"allowed: \.png, \.pdf, \.svg"),
    ("plot {run.h5} -o nodir/p.png", "no folder nodir"),
    # view
    ("view {run.h5} -o v.txt", r"allowed: \.html"),
    ("view {run.h5} --max-samples 1 -o v.html", "max-samples"),
    ("view missing.h5 -o v.html", "no such file"),
    ("view {ds.h5} --run 99 -o v.html", "99"),
    # torques
    ("torques missing.h5", "no such file"),
    ("torques {empty.csv}", "unknown run file type '.csv'"),
    ("torques {run.h5} --run 1", "--run is .*run file"),
    ("torques {run.h5} --plot t.jpg", r"allowed: \.png"),
    ("torques {ds.h5} --run 99", "99"),
    # mjcf
    ("mjcf --robot nope -o m.xml", "--robot is 'nope'"),
    ("mjcf --robot ur5 --tool nope -o m.xml", "frame 'nope' .*allowed: a link, base_link"),
    ("mjcf --urdf {origin.urdf} -o m.xml", r"link 'dh0' .*<origin xyz> is '0 0'; allowed: three"),
    ("mjcf --preset aaria-fig2 --rate nan -o m.xml", "--rate is nan"),
    ("mjcf --preset aaria-fig2 --density -1 -o m.xml", "density"),
    ("mjcf --preset aaria-fig2 -o m.txt", r"allowed: \.xml"),
    ("mjcf --preset aaria-fig2 --urdf {origin.urdf} -o m.xml", "give one robot"),
    ("mjcf --from {empty.csv} -o m.xml", "unknown run file type"),
    # arm
    ("arm urdf -o arm --radius nan", "radius is nan"),
    ("arm urdf -o arm --preset nope", "allowed: pick-place-arm"),
    ("arm urdf -o existing.h5", "existing.h5"),
    ("arm pick-place --cylinder nan 0.1 --place 0.3 -0.1 -o pp.h5", "cylinder x is nan"),
    ("arm pick-place --cylinder 5 0.1 --place 0.3 -0.1 -o pp.h5", "out of reach"),
    ("arm pick-place --cylinder 0.3 0.1 --place 0.3 -0.1 --rate 0 -o pp.h5", "--rate is 0"),
    ("arm pick-place --cylinder 0.3 0.1 --place 0.3 -0.1 --mass -1 -o pp.h5", "mass -1"),
    ("arm pick-place --cylinder 0.3 0.1 --place 0.3 -0.1 --fps 0 -o pp.h5", "--fps 0"),
    ("arm pick-place --cylinder 0.3 0.1 --place 0.3 -0.1 --gif-size 5 -o pp.h5", "--gif-size"),
    (
        "arm pick-place --cylinder 0.3 0.1 --place 0.3 -0.1 -o existing.h5 --sheet nodir/s.png",
        "no folder nodir",
    ),
    (
        "arm pick-place --cylinder 0.3 0.1 --place 0.3 -0.1 -o existing.h5 --animation a.png",
        r"allowed: \.gif",
    ),
    ("arm pick-place --cylinder 0.3 0.1 --place 0.3 -0.1 -o pp.txt", r"allowed: \.h5"),
    # dataset-stats
    ("dataset-stats missing.h5", "no such file"),
    ("dataset-stats {run.h5}", "not an aaria_pin data set"),
    ("dataset-stats {ds.h5} --fractions a,b", "--fractions is 'a,b'"),
    ("dataset-stats {ds.h5} --names nope", "nope"),
    ("dataset-stats {ds.h5} --split bad", "bad"),
    # robots, the group itself
    ("robots --bogus", "No such option"),
    ("nope", "No such command"),
    # wrist (done)
    ("wrist workspace --theta2 0 inf", "--theta2 is inf"),
    ("wrist fk nan 0 0", "JOINTS holds nan"),
    ("wrist ik --angles nan 0 0", "nan"),
    ("wrist simulate 60 45 -30 -o w.txt", r"allowed: \.h5"),
    # template (done)
    ("template nope -o t.csv", "nope"),
    # simulate (H1)
    ("simulate --dh {empty.npy} -o s.h5", "empty"),
    ("simulate --urdf {origin.urdf} -o s.h5", r"<origin xyz> is '0 0'"),
    ("simulate --preset aaria-fig2 --duration nan -o s.h5", "--duration"),
    ("simulate --preset aaria-fig2 -o s.jpg", r"allowed: \.h5"),
    ("simulate --preset aaria-fig2 -o {long}.h5", "bytes"),
    # dataset (H11)
    pytest.param("dataset -n 4 --dh {nan.csv} --overwrite -o existing.h5", "nan"),
    pytest.param("dataset -n 4 --joints {nan.csv} -o d.h5", "nan"),
    pytest.param("dataset -n 4 --dh {short.csv} --overwrite -o existing.h5", r"shape \(3, 5\)"),
    pytest.param("dataset -n 2 --config {not_utf8.toml} -o d.h5", "UTF-8"),
    pytest.param("dataset -n 2 --config {long.toml} -o d.h5", r"\ba\b.*long"),
    pytest.param("dataset -n 2 --config {huge.toml} -o d.h5", r"\(a\) is|\ba = "),
    pytest.param("dataset -n 2 --scheduler '' -o d.h5", "--scheduler"),
    pytest.param("dataset -n 2 -o -", "not a file path"),
    pytest.param("dataset -n 2 -o d.txt", r"allowed: \.h5"),
    # info (H11)
    pytest.param("info missing.h5", "no such file"),
    pytest.param("info {adir}", "directory|folder"),
    # identify (H5, registered by the lead)
    pytest.param("identify missing.h5 -o t.csv", "no such file"),
]


def _argv(text: str, inputs: Path) -> list[str]:
    import re
    import shlex

    names = {path.name: str(path) for path in inputs.iterdir()} | {"long": LONG_NAME}
    return [
        re.sub(r"\{([\w.]+)\}", lambda match: names[match.group(1)], part)
        for part in shlex.split(text)
    ]


@pytest.mark.parametrize(("text", "pattern"), CASES)
def test_bad_input_one_line_exit_2_nothing_written(
    text: str, pattern: str, work: Path, inputs: Path
) -> None:
    import re
    import signal

    def hang(*_: object) -> None:
        raise TimeoutError(f"no answer within {TIME_LIMIT} s: {text}")

    argv = _argv(text, inputs)
    before = listing(work, inputs)
    previous = signal.signal(signal.SIGALRM, hang)
    signal.alarm(TIME_LIMIT)
    try:
        result = CliRunner().invoke(main, argv)
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    after = listing(work, inputs)
    assert result.exit_code == 2, (result.exit_code, result.output, result.exception)
    assert isinstance(result.exception, SystemExit), result.exception
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("aaria: error: "), result.stderr
    assert "Traceback" not in result.output
    assert re.search(pattern, lines[0]), lines[0]
    assert not re.search(r"np\.\w+\(|array\(", lines[0])  # numbers shown plainly
    assert after == before


def test_an_input_fifo_is_refused_at_once(work: Path) -> None:
    """A FIFO as input would make a reader wait for a writer forever: refused in one line."""
    fifo = work / "table.csv"
    os.mkfifo(fifo)
    cases = (
        ["urdf", "--dh", str(fifo), "-o", "r.urdf"],
        ["plot", str(fifo), "-o", "p.png"],
        ["simulate", "--urdf", str(fifo), "-o", "s.h5"],  # the issue's own hang
        ["mjcf", "--urdf", str(fifo), "-o", "m.xml"],
        ["dataset", "-n", "2", "--config", str(fifo), "-o", "d.h5"],
        ["simulate", "--robot", "ur5", "--imu-layout", str(fifo), "-o", "s.h5"],
    )
    for argv in cases:
        done = subprocess.run(
            [sys.executable, "-m", "aaria_pin.cli", *argv],
            capture_output=True,
            text=True,
            timeout=60,
            cwd=work,
        )
        assert done.returncode == 2, done.stderr
        assert done.stderr.count("\n") == 1 and "FIFO" in done.stderr, done.stderr
        assert sorted(p.name for p in work.iterdir()) == ["existing.h5", "table.csv"], argv
