"""Options that do not go together, and the rate bound, over every command: one line, exit 2.

Each conflict case gives the argv, the two flags the message must name and the message's start:
the command runs in a fresh working folder (in process, through click's runner) and must exit
with status 2, print one line on stderr (``aaria: error: …``, no traceback) naming both flags,
and leave the working folder and the shared inputs as they were. The inputs are real files
made by the tool (``aaria simulate``, ``aaria dataset``, ``aaria template``).

The rate bound is one constant (:data:`aaria_pin.core.trajectory.MAX_RATE`): every command that
takes a rate refuses the same rate above it with the same words, and takes it at the bound.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli

from aaria_pin.core.trajectory import MAX_RATE
from tests.cli.test_bad_input import listing

PICK_PLACE = "arm pick-place --cylinder 0.35 0.1 --place 0.2 -0.3 -o pp.h5"
"""A pick-and-place task that runs (its picture options are the conflicts)."""


@pytest.fixture(scope="module")
def inputs(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """DH and ur5 runs (0.2 s at 100 Hz), a two-run data set, torques, a trajectory, tables."""
    folder = tmp_path_factory.mktemp("conflict_inputs")
    made = (
        ["simulate", "--preset", "aaria-fig2", "--duration", "0.2", "-o", f"{folder}/run.h5"],
        ["simulate", "--robot", "ur5", "--duration", "0.2", "-o", f"{folder}/ur5.h5"],
        [
            "dataset",
            "-n",
            "2",
            "--duration",
            "0.2",
            "--workers",
            "1",
            "--quiet",
            "-o",
            f"{folder}/ds.h5",
        ],
        ["template", "joints", "-o", f"{folder}/joints.csv"],
        ["template", "base", "-o", f"{folder}/base.csv"],
    )
    for argv in made:
        code, _, err = run_cli(*argv)
        assert code == 0, err
    time = np.arange(21) / 100.0
    np.save(folder / "tau.npy", np.zeros((21, 6)))
    np.save(folder / "motion.npy", np.column_stack([time, 0.1 * np.sin(np.outer(time, [1] * 6))]))
    return folder


@pytest.fixture
def work(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A fresh, empty working folder as the cwd."""
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _argv(text: str, inputs: Path) -> list[str]:
    return [re.sub(r"\{([\w.]+)\}", lambda m: str(inputs / m.group(1)), p) for p in text.split()]


CONFLICTS = [
    # options that would be ignored
    ("dataset -n 2 --quiet --progress-every 5 -o d.h5", "--progress-every is given with --quiet"),
    ("template dh --overwrite", "--overwrite is given without --output"),
    ("dataset-stats {ds.h5} --split all --seed 5", "--seed is given with --split all"),
    (
        "dataset-stats {ds.h5} --split all --fractions 0.5,0.3,0.2",
        "--fractions is given with --split all",
    ),
    # identify: an option of another mode (the library's IdentifyRequest)
    ("identify {run.h5} --parameters", "--parameters is given without --dynamics"),
    ("identify {run.h5} --holdout 0.3", "--holdout is given without --dynamics"),
    ("identify --dataset {ds.h5} --holdout 0.3", "--holdout is given without --dynamics"),
    ("identify {run.h5} --workers 2", "--workers is given without --dataset"),
    ("identify --dynamics {run.h5} --limit 2", "--limit is given without --dataset"),
    ("identify {run.h5} --plot c.png", "--plot is given without --dataset"),
    ("identify --dataset {ds.h5} --run 0", "--run is given with --dataset"),
    ("identify --dynamics {run.h5} --urdf a.urdf", "--urdf is given with --dynamics"),
    ("identify --dataset {ds.h5} --urdf a.urdf", "--urdf is given with --dataset"),
    ("identify --dataset --dynamics {ds.h5} --parameters", "--parameters is given with --dataset"),
    # simulate: the motion (the library's MotionChoice and chosen_motion)
    (
        "simulate --preset aaria-fig2 --drive torque --torques {tau.npy} --motion fourier -o s.h5",
        "--motion is given with --torques",
    ),
    (
        "simulate --preset aaria-fig2 --drive torque --torques {tau.npy} --motion sine -o s.h5",
        "--motion is given with --torques",
    ),
    (
        "simulate --robot ur5 --drive torque --torques {run.h5} --motion fourier -o s.h5",
        "--motion is given with --torques",
    ),
    (
        "simulate --preset aaria-fig2 --drive torque --torques {tau.npy} --trajectory "
        "{motion.npy} -o s.h5",
        "--trajectory is given with --torques",
    ),
    (
        "simulate --preset aaria-fig2 --motion fourier --trajectory {motion.npy} -o s.h5",
        "--motion is given with --trajectory",
    ),
    ("simulate --preset aaria-fig2 --harmonics 3 -o s.h5", "--harmonics is given without --motion"),
    (
        "simulate --preset aaria-fig2 --motion sine --base-frequency 0.2 -o s.h5",
        "--base-frequency is given without --motion fourier",
    ),
    ("simulate --robot ur5 --smoothing 0.1 -o s.h5", "--smoothing is given without --trajectory"),
    (
        "simulate --preset aaria-fig2 --joints {joints.csv} --motion fourier -o s.h5",
        "--joints is given with --motion fourier",
    ),
    (
        "simulate --preset aaria-fig2 --joints {joints.csv} --trajectory {motion.npy} -o s.h5",
        "--joints is given with --trajectory",
    ),
    ("simulate --from {run.h5} --harmonics 2 -o s.h5", "--harmonics is given without --motion"),
    # simulate: the robot's source
    (
        "simulate --preset aaria-fig2 --convention standard -o s.h5",
        "--convention is given with --preset",
    ),
    ("simulate --robot ur5 --convention standard -o s.h5", "--convention is given with --robot"),
    ("simulate --robot ur5 --density 3000 -o s.h5", "--density is given with --robot"),
    ("simulate --robot ur5 --imu-mount {run.h5} -o s.h5", "--imu-mount is given with --robot"),
    (
        "simulate --robot ur5 --fixed-base --base {base.csv} -o s.h5",
        "--base is given with --fixed-base",
    ),
    ("simulate --from {run.h5} --preset aaria-fig2 -o s.h5", "--preset is given with --from"),
    ("simulate --from {ur5.h5} --robot ur5 -o s.h5", "--robot is given with --from"),
    ("simulate --from {ur5.h5} --density 3000 -o s.h5", "--density is given with --from"),
    ("simulate --preset aaria-fig2 --tool tool0 -o s.h5", "--tool .*--robot"),
    ("simulate --preset aaria-fig2 --drive torque -o s.h5", "--drive torque and --torques"),
    ("simulate --preset aaria-fig2 --torques {tau.npy} -o s.h5", "--drive torque and --torques"),
    # mjcf, urdf
    ("mjcf --robot ur5 --density 3000 -o m.xml", "--density is given with --robot"),
    ("mjcf --robot ur5 --convention standard -o m.xml", "--convention is given with --robot"),
    ("mjcf --preset aaria-fig2 --tool tool0 -o m.xml", "--tool is given with --preset"),
    ("mjcf --dh {joints.csv} --imu-layout x.toml -o m.xml", "--imu-layout is given with --dh"),
    ("mjcf --from {run.h5} --density 3000 -o m.xml", "--density is given with --from"),
    ("mjcf --from {run.h5} --convention modified -o m.xml", "--convention is given with --from"),
    ("urdf --preset aaria-fig2 --convention standard -o u.urdf", "--convention .*--preset"),
    # the readers' commands
    ("torques {ds.h5} --plot t.png", "--plot is given without --run"),
    ("render --preset aaria-fig2 --time 0.1 -o p.png", "--time is given without --from"),
    ("render --preset aaria-fig2 --run 1 -o p.png", "--run is given without --from"),
    (
        "render --preset aaria-fig2 --convention standard -o p.png",
        "--convention is given without --dh",
    ),
    # the rest
    ("robots --json --check", "--check is given with --json"),
    ("robots --json --paths", "--paths is given with --json"),
    (f"{PICK_PLACE} --fps 15", "--fps is given without --animation"),
    (f"{PICK_PLACE} --gif-size 400", "--gif-size is given without --animation"),
    ("dataset -n 2 --shards sh -o d.h5", "--shards .*--scheduler"),
    (
        "wrist ik --angles 1 2 3 --matrix 1 0 0 0 1 0 0 0 1",
        "give exactly one of --angles .*--matrix",
    ),
]
"""``(argv, message)``: the message's start; its two flags are the first two it names."""


@pytest.mark.parametrize(("text", "message"), CONFLICTS)
def test_conflicting_options_name_both_exit_2_nothing_written(
    text: str, message: str, work: Path, inputs: Path
) -> None:
    before = listing(work, inputs)
    code, stdout, stderr = run_cli(*_argv(text, inputs))
    assert code == 2, (stdout, stderr)
    lines = stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("aaria: error: "), stderr
    assert re.match(message, lines[0].removeprefix("aaria: error: ")), lines[0]
    flags = re.findall(r"--[a-z][a-z-]*", message)
    assert len(set(flags)) == 2 and all(flag in lines[0] for flag in flags)
    if " is given " in message:  # the library's wording: what is allowed, with the same flags
        first, other = flags
        wanted = "with" if " is given without " in message else "without"
        assert f"; allowed: {first} {wanted} {other}" in lines[0]
    assert listing(work, inputs) == before


RATE_COMMANDS = [
    "simulate --preset aaria-fig2 --duration 0.01 --rate {rate} -o s.h5",
    "dataset -n 1 --duration 0.01 --rate {rate} --workers 1 --quiet -o d.h5",
    "wrist simulate 1 2 3 --duration 0.01 --rate {rate} -o w.h5",
    "mjcf --preset aaria-fig2 --rate {rate} -o m.xml",
    "mjcf --from {run.h5} --rate {rate} -o m.xml",
    f"{PICK_PLACE} --rate {{rate}}",
]


@pytest.mark.parametrize("text", RATE_COMMANDS)
def test_one_rate_bound_for_every_command(text: str, work: Path, inputs: Path) -> None:
    code, _, stderr = run_cli(*_argv(text.replace("{rate}", "1e12"), inputs))
    assert code == 2
    assert stderr == f"aaria: error: --rate is 1e+12; allowed: 0 < rate <= {MAX_RATE:g} Hz\n"
    assert list(work.iterdir()) == []


def test_the_bound_itself_is_taken(work: Path, inputs: Path) -> None:
    for text in (RATE_COMMANDS[0], RATE_COMMANDS[3]):
        code, _, stderr = run_cli(*_argv(text.replace("{rate}", f"{MAX_RATE:g}"), inputs))
        assert code == 0, stderr
