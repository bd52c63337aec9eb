"""``aaria identify``: --dynamics on a run file and a data set run, --dataset over a tiny data set.

The numbers of each identification are checked in ``tests/apps/test_identify_*.py``; here the
command's dispatch, its report and table against the per-run numbers (recomputed with numpy),
its outputs, and its refusals (exit 2, one line, nothing written).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from conftest import run_cli

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.files.runfile import write_run


@pytest.fixture(scope="module")
def run_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    preset = get_preset("aaria-fig3")
    record = simulate_run(
        preset.table, preset.joint_table, preset.base_table, duration=3.0, rate=50.0, noise=False
    )
    path = tmp_path_factory.mktemp("identify") / "run.h5"
    write_run(path, record)
    return path


@pytest.fixture(scope="module")
def tiny_dataset(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("identify") / "tiny.h5"
    code, _, err = run_cli(
        "dataset", "-n", "3", "--duration", "2", "--rate", "40", "--no-noise", "--workers", "1",
        "--dtype", "float64", "--quiet", "-o", str(path),
    )  # fmt: skip
    assert code == 0, err
    return path


def test_dynamics_on_a_run_file_writes_its_report(run_file: Path, tmp_path: Path) -> None:
    report_path = tmp_path / "report.json"
    code, out, err = run_cli(
        "identify", "--dynamics", str(run_file), "--json", "-o", str(report_path)
    )
    assert code == 0, err
    report = json.loads(out)
    assert json.loads(report_path.read_text()) == report
    assert report["n_base"] < report["n_standard"]
    # noise-free torques: the held-out samples are predicted to rounding
    assert max(v for v in report["holdout_relative_rms"].values() if v is not None) < 1e-6
    mass = report["total_mass"]
    assert mass["estimate"] == pytest.approx(mass["model"], rel=1e-6)
    code, out, _ = run_cli(
        "identify", "--dynamics", str(run_file), "--parameters", "--holdout", "0.3"
    )
    assert code == 0 and "total mass" in out and " = " in out


def test_dynamics_on_a_dataset_run(tiny_dataset: Path) -> None:
    code, out, err = run_cli("identify", "--dynamics", str(tiny_dataset), "--run", "1", "--json")
    assert code == 0, err
    report = json.loads(out)
    assert max(v for v in report["holdout_relative_rms"].values() if v is not None) < 1e-6


def test_dataset_benchmark_table_report_and_plot(tiny_dataset: Path, tmp_path: Path) -> None:
    report_path, plot = tmp_path / "bench.json", tmp_path / "cdf.png"
    code, out, err = run_cli(
        "identify", "--dataset", str(tiny_dataset), "--workers", "1", "--json",
        "-o", str(report_path), "--plot", str(plot),
    )  # fmt: skip
    assert code == 0, err
    report = json.loads(out)
    assert json.loads(report_path.read_text()) == report
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    runs = report["runs"]
    assert [r["run"] for r in runs] == [0, 1, 2]
    assert {
        "dataset", "run", "noise", "duration", "rate", "link_types", "link_types_right",
        "tool_tip_rms", "tool_tip_max", "axis_angle_max", "seconds", "error",
    } <= set(runs[0])  # fmt: skip
    (group,) = report["groups"]
    assert (group["noise"], group["duration_s"], group["rate_hz"], group["runs"]) == (
        False, 2.0, 40.0, 3,
    )  # fmt: skip
    rms = np.array([r["tool_tip_rms"] for r in runs])
    assert group["tool_tip_rms_median_m"] == pytest.approx(np.median(rms))
    assert group["tool_tip_rms_max_m"] == pytest.approx(np.max(rms))
    assert group["within_1mm_share"] == pytest.approx(np.mean(rms <= 1e-3))
    assert group["link_types_right_share"] == pytest.approx(
        np.mean([r["link_types_right"] for r in runs])
    )
    # noise-free runs: every structure right, every tool tip within a millimetre
    assert group["link_types_right_share"] == 1.0 and group["within_1mm_share"] == 1.0
    # the text table names the group
    code, out, _ = run_cli("identify", "--dataset", str(tiny_dataset), "--limit", "1")
    assert code == 0 and "no noise, 2 s at 40 Hz" in out and "types right" in out


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (["--dataset", "{run}"], "not an aaria_pin data set"),
        (["--dataset", "{ds}", "--plot", "{tmp}/cdf.txt"], "picture"),
        (["--dataset", "{ds}", "--run", "0"], "--run"),
        (["{run}", "{ds}"], "2 files"),
        (["--dynamics", "{run}", "-o", "{tmp}/report.csv"], "JSON report"),
        (["--dynamics", "{run}", "--urdf", "{tmp}/a.urdf"], "--urdf"),
        (["--dynamics", "{ds}"], "--run"),
        (["{run}", "--plot", "{tmp}/cdf.png"], "--plot"),
        (
            ["{run}", "--holdout", "0.3"],
            "--holdout is given without --dynamics; allowed: --holdout with --dynamics",
        ),
        (["--dynamics", "{run}", "--workers", "2"], "--workers is given without --dataset"),
        (
            ["--dataset", "{ds}", "--dynamics", "--parameters"],
            "--parameters is given with --dataset",
        ),
        ([], "no FILE"),
        (["{run}", "--start", "{tmp}/none.npy"], "--start {tmp}/none.npy: no such file"),
        (["--dynamics", "{run}", "--start", "{run}"], "--start is given with --dynamics"),
    ],
)
def test_bad_inputs_exit_2_one_line_nothing_written(
    arguments: list[str], message: str, run_file: Path, tiny_dataset: Path, tmp_path: Path
) -> None:
    values = {"run": str(run_file), "ds": str(tiny_dataset), "tmp": str(tmp_path)}
    code, _, err = run_cli("identify", *(a.format(**values) for a in arguments))
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and message.format(**values) in err
    assert list(tmp_path.iterdir()) == []


def test_a_start_table_is_fitted_first_and_a_bad_one_refused(
    run_file: Path, tmp_path: Path
) -> None:
    table = np.asarray(get_preset("aaria-fig3").table, dtype=float)
    np.save(tmp_path / "truth.npy", table)
    code, out, err = run_cli("identify", str(run_file), "--start", str(tmp_path / "truth.npy"),
                             "--json")  # fmt: skip
    assert code == 0, err
    report = json.loads(out)
    assert report["fit"]["start"] == "start table" and report["fit"]["closed_form"] is False
    assert report["link_types"] == [int(t) for t in table[:6, 4]]
    np.save(tmp_path / "short.npy", table[:7])
    code, out, err = run_cli("identify", str(run_file), "--start", str(tmp_path / "short.npy"))
    assert code == 2 and out == ""
    assert err.strip() == (
        "aaria: error: --start is a table of shape (7, 5); allowed: 8 × 5 (senSenDH: rows 1-6 "
        "modules, 7 tool, 8 base)"
    )
