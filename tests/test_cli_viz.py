"""aaria render, plot and view from the command line: files written, bad input refused."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

pytest.importorskip("matplotlib")

from aaria_pin.cli import main
from aaria_pin.presets import get_preset
from aaria_pin.runfile import write_run
from aaria_pin.simulate import simulate_run
from aaria_pin.wrist_run import simulate_wrist, write_wrist_run


def run(*args: str):
    return CliRunner().invoke(main, list(args))


def png_size(path: Path) -> tuple[int, int]:
    from PIL import Image

    with Image.open(path) as image:
        return image.size


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("cli")
    record = simulate_run(get_preset("aaria-fig3").table, duration=2.0, rate=50.0)
    wrist = simulate_wrist(np.radians([30.0, 20.0, 10.0]), start=0.1, rate=50.0)
    table = folder / "table.csv"
    np.savetxt(table, get_preset("aaria-fig2").table, delimiter=",")
    return {
        "run": write_run(folder / "run.h5", record),
        "wrist": write_wrist_run(folder / "wrist.mat", wrist),
        "table": table,
    }


def test_render_preset_table_and_runs(tmp_path: Path, files: dict[str, Path]) -> None:
    cases = [
        ["--preset", "aaria-fig2"],
        ["--dh", str(files["table"])],
        ["--preset", "spherical-wrist"],
        ["--from", str(files["run"]), "--time", "1.5"],
        ["--from", str(files["wrist"])],
    ]
    for k, source in enumerate(cases):
        out = tmp_path / f"pic{k}.png"
        result = run("render", *source, "--width", "500", "--height", "400", "-o", str(out))
        assert result.exit_code == 0, result.output
        assert png_size(out) == (500, 400)
    assert "t = 1.500 s" in run("render", *cases[3], "-o", str(tmp_path / "t.png")).output
    assert "table.csv" in run("render", *cases[1], "-o", str(tmp_path / "d.png")).output


def test_plot_and_view_of_both_run_kinds(tmp_path: Path, files: dict[str, Path]) -> None:
    for name in ("run", "wrist"):
        png, page = tmp_path / f"{name}.png", tmp_path / f"{name}.html"
        result = run("plot", str(files[name]), "-o", str(png))
        assert result.exit_code == 0, result.output
        assert png.stat().st_size > 10_000
        result = run("view", str(files[name]), "--max-samples", "40", "-o", str(page))
        assert result.exit_code == 0, result.output
        assert " 40 of " in result.output and "<canvas" in page.read_text(encoding="utf-8")
    result = run("plot", str(files["run"]), "--imu", "imu_link1_a", "-o", str(tmp_path / "i.png"))
    assert result.exit_code == 0 and "6 panels" in result.output


@pytest.mark.parametrize(
    ("args", "pattern"),
    [
        (["render", "--from", "{run}", "--time", "99", "-o", "{out}.png"], "outside the run"),
        (["render", "--preset", "aaria-fig2", "--from", "{run}", "-o", "{out}.png"], "one of"),
        (["render", "-o", "{out}.png"], "exactly one of --preset NAME, --dh FILE or --from"),
        (["render", "--preset", "aaria-fig2", "--time", "1", "-o", "{out}.png"], "--from"),
        (["render", "--preset", "nope", "-o", "{out}.png"], "not known"),
        (["render", "--preset", "aaria-fig2", "-o", "{out}.jpg"], "allowed: .png"),
        (["render", "--preset", "aaria-fig2", "--width", "5", "-o", "{out}.png"], "100 to"),
        (["plot", "{run}", "--imu", "imu_link2_a", "-o", "{out}.png"], "not in the run"),
        (["plot", "{wrist}", "--imu", "imu_tool", "-o", "{out}.png"], "no IMUs"),
        (["plot", "{table}", "-o", "{out}.png"], "unknown|not a run file"),
        (["view", "{missing}", "-o", "{out}.html"], "no such file"),
        (["view", "{run}", "-o", "{out}.txt"], "allowed: .html"),
    ],
)
def test_bad_input_one_line_exit_2_nothing_written(
    tmp_path: Path, files: dict[str, Path], args: list[str], pattern: str
) -> None:
    import re

    values = {k: str(v) for k, v in files.items()}
    values |= {"out": str(tmp_path / "out"), "missing": str(tmp_path / "missing.h5")}
    result = run(*(a.format(**values) for a in args))
    assert result.exit_code == 2, result.output
    assert re.search(pattern, result.output), result.output
    assert len(result.output.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []
