"""Start-up of the ``aaria`` process: what ``aaria simulate`` imports, and how it ends.

The speed goals themselves live in ``benchmarks/bench_cli.py``; these tests pin the causes:
the modules a short DH run loads, and the collector frozen as the process ends.
"""

from __future__ import annotations

import gc
import json
import subprocess
import sys
from pathlib import Path

import pytest

from aaria_pin.cli import main

# Run the command as the console script does (``main()``, arguments from sys.argv) and write the
# modules loaded and the frozen-object count at exit to a JSON file.
PROBE = """
import atexit, gc, json, sys
out = sys.argv.pop(1)
def report():
    with open(out, "w") as f:
        json.dump({"modules": sorted(sys.modules), "frozen": gc.get_freeze_count()}, f)
atexit.register(report)
from aaria_pin.cli import main
sys.argv[0] = "aaria"
main()
"""

NOT_NEEDED = (
    "scipy.linalg",
    "scipy.signal",
    "scipy.stats",
    "scipy.io",
    "matplotlib",
    "trimesh",
    "yourdfpy",
    "dask",
    "example_robot_data",
)
"""Modules a DH run to .h5 does not need (numba needs only ``scipy`` itself)."""


def _simulate_process(tmp_path: Path, *flags: str) -> dict[str, object]:
    report = tmp_path / "report.json"
    run = tmp_path / "run.h5"
    argv = ["simulate", "--preset", "aaria-fig2", "--duration", "1", *flags, "-o", str(run)]
    subprocess.run([sys.executable, "-c", PROBE, str(report), *argv], check=True)
    assert run.is_file()
    result: dict[str, object] = json.loads(report.read_text())
    return result


def test_a_noiseless_dh_run_imports_only_what_it_needs(tmp_path: Path) -> None:
    report = _simulate_process(tmp_path, "--no-noise")
    loaded = set(report["modules"])  # type: ignore[call-overload]
    assert {"numba", "pinocchio", "h5py"} <= loaded
    assert sorted(loaded.intersection(NOT_NEEDED)) == []


def test_a_noisy_dh_run_imports_only_what_it_needs(tmp_path: Path) -> None:
    loaded = set(_simulate_process(tmp_path)["modules"])  # type: ignore[call-overload]
    assert sorted(loaded.intersection(NOT_NEEDED)) == []


def test_the_process_freezes_the_collector_as_it_ends(tmp_path: Path) -> None:
    report = _simulate_process(tmp_path, "--no-noise")
    assert isinstance(report["frozen"], int) and report["frozen"] > 0


def test_a_caller_passing_arguments_keeps_its_collector() -> None:
    before = gc.get_freeze_count()
    with pytest.raises(SystemExit):
        main(["--version"])
    main(["robots", "--help"], standalone_mode=False)
    assert gc.get_freeze_count() == before
