"""The analysis scripts run (quick mode) and write their table and plot."""

from __future__ import annotations

import csv
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.slow
@pytest.mark.parametrize("script", ["peak_torque_vs_link", "base_load_by_configuration"])
def test_analysis_script_writes_a_table_and_a_plot(tmp_path: Path, script: str) -> None:
    subprocess.run(
        [
            sys.executable,
            str(ROOT / "analysis" / f"{script}.py"),
            "--quick",
            "--out",
            str(tmp_path),
        ],
        check=True,
        capture_output=True,
    )
    rows = list(csv.DictReader(open(tmp_path / f"{script}.csv")))
    assert len(rows) >= 9
    assert (tmp_path / f"{script}.png").read_bytes()[:4] == b"\x89PNG"
    if script == "peak_torque_vs_link":  # heavier and longer arms need more torque
        steel = [float(r["peak_tau_joint2_Nm"]) for r in rows if r["material"] == "steel"]
        abs_ = [float(r["peak_tau_joint2_Nm"]) for r in rows if r["material"] == "ABS plastic"]
        assert steel == sorted(steel) and steel[-1] > abs_[-1]
