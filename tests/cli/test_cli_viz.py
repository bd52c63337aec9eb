"""aaria render, plot and view from the command line: files written, bad input refused."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner, Result

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.apps.wrist.run import simulate_wrist, write_wrist_run
from aaria_pin.cli import main
from aaria_pin.files.runfile import write_run


def run(*args: str) -> Result:
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
    assert result.exit_code == 0 and "8 panels" in result.output  # fig3: both joint kinds


def test_plot_of_a_urdf_run_keeps_torques_apart_from_forces(tmp_path: Path) -> None:
    run_file = tmp_path / "ur5.h5"
    args = ["simulate", "--robot", "ur5", "--duration", "1", "--rate", "20", "-o", str(run_file)]
    assert run(*args).exit_code == 0
    result = run("plot", str(run_file), "--imu", "imu_base", "-o", str(tmp_path / "u.png"))
    assert result.exit_code == 0, result.output
    assert "6 panels" in result.output  # revolute joints only, base wrench, one IMU
    assert png_size(tmp_path / "u.png")[0] == 1400


def isolate_plugins(monkeypatch: pytest.MonkeyPatch, *plugins: str) -> None:
    from aaria_pin.viz import sources

    monkeypatch.setattr(sources, "_PLUGINS", plugins)
    monkeypatch.setattr(sources, "_PRESETS", {})
    monkeypatch.setattr(sources, "_plugins_loaded", False)


def test_render_pick_place_arm_without_its_plugin_is_one_clear_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    isolate_plugins(monkeypatch, "aaria_pin_missing_plugin")
    result = run("render", "--preset", "pick-place-arm", "-o", str(tmp_path / "arm.png"))
    assert result.exit_code == 2, result.output
    assert len(result.output.strip().splitlines()) == 1
    assert "'pick-place-arm' is a model preset" in result.output
    assert "allowed: aaria-fig2, aaria-fig3, spherical-wrist" in result.output
    assert list(tmp_path.iterdir()) == []


def test_render_draws_a_plugin_preset_and_lists_it(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import sys

    (tmp_path / "aaria_cli_preset_plugin.py").write_text(
        "from aaria_pin.aaria.presets import get_preset\n"
        "from aaria_pin.viz.sources import table_view\n"
        "P = get_preset('aaria-fig3')\n"
        "PRESETS = {'demo-arm': lambda: table_view(P.table, P.convention, 'demo arm')}\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    isolate_plugins(monkeypatch, "aaria_cli_preset_plugin")
    try:
        out = tmp_path / "demo.png"
        result = run("render", "--preset", "demo-arm", "--width", "300", "-o", str(out))
        assert result.exit_code == 0, result.output
        assert png_size(out) == (300, 800) and "demo arm" in result.output
        result = run("render", "--preset", "nope", "-o", str(tmp_path / "n.png"))
        assert result.exit_code == 2 and "spherical-wrist, demo-arm" in result.output
    finally:
        sys.modules.pop("aaria_cli_preset_plugin", None)


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
        (["plot", "{old_wrist}", "--imu", "imu_tool", "-o", "{out}.png"], "no IMUs"),
        (["plot", "{table}", "-o", "{out}.png"], "unknown|not a run file"),
        (["view", "{missing}", "-o", "{out}.html"], "no such file"),
        (["view", "{run}", "-o", "{out}.txt"], "allowed: .html"),
        (["plot", "{run}", "-o", "{out}.jpg"], r"'\.jpg' .*allowed: \.png, \.pdf, \.svg$"),
        (["render", "--preset", "aaria-fig2", "-o", "{out}.eps"], r"allowed: \.png, \.pdf, \.svg$"),
        (["torques", "{run}", "--plot", "{out}.gif"], r"allowed: \.png, \.pdf, \.svg$"),
        (["render", "--from", "{missing}", "-o", "{out}.png"], "no such file"),
    ],
)
def test_bad_input_one_line_exit_2_nothing_written(
    tmp_path: Path, files: dict[str, Path], args: list[str], pattern: str
) -> None:
    import re

    values = {k: str(v) for k, v in files.items()}
    values |= {"out": str(tmp_path / "out"), "missing": str(tmp_path / "missing.h5")}
    values["old_wrist"] = str(Path(__file__).parents[1] / "fixtures" / "v0_1_0" / "wrist_run.h5")
    result = run(*(a.format(**values) for a in args))
    assert result.exit_code == 2, result.output
    assert re.search(pattern, result.output), result.output
    assert len(result.output.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_render_pick_place_arm_through_the_arm_plugin(tmp_path: Path) -> None:
    """The arm's plug-in gives the preset; render draws it (the arm at rest)."""
    from aaria_pin.viz.sources import preset_names

    assert "pick-place-arm" in preset_names()
    out = tmp_path / "arm.png"
    result = run("render", "--preset", "pick-place-arm", "--width", "400", "--height", "300",
                 "-o", str(out))  # fmt: skip
    assert result.exit_code == 0, result.output
    assert png_size(out) == (400, 300)


def test_torques_print_every_peak_with_its_unit(files: dict[str, Path]) -> None:
    """fig3 has prismatic modules 1 and 5 (forces, N) and revolute ones (torques, N*m)."""
    import re

    result = run("torques", str(files["run"]))
    assert result.exit_code == 0, result.output
    rows = {line.split()[1]: line for line in result.output.splitlines() if line[:1].isdigit()}
    types = {joint: line.split()[2] for joint, line in rows.items()}
    assert set(types.values()) == {"prismatic", "revolute"}
    for joint, line in rows.items():
        unit = "N" if types[joint] == "prismatic" else "N*m"
        assert re.search(rf"\s[\d.e+-]+ {re.escape(unit)}\s", line), line
    wrench = result.output.splitlines()[-1]
    assert re.fullmatch(
        r"base wrench peaks: (f[xyz] [\d.e+-]+ N, ){3}(m[xyz] [\d.e+-]+ N\*m(, )?){3}", wrench
    ), wrench
