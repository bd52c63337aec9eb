"""Pictures for papers: PDF and SVG, legends, RGB frame axes, grouped RMS bars, equal axes, GIFs."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner, Result

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.cli import main
from aaria_pin.files.runfile import read_run, write_run
from aaria_pin.viz.scene import AXIS_COLOURS, posed_geometry
from aaria_pin.viz.sources import preset_view


def run(*args: str) -> Result:
    return CliRunner().invoke(main, list(args))


@pytest.fixture(scope="module")
def fig2_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    record = simulate_run(get_preset("aaria-fig2").table, duration=2.0, rate=50.0)
    return write_run(tmp_path_factory.mktemp("pictures") / "fig2.h5", record)


def test_render_writes_valid_pdf_and_svg(tmp_path: Path, fig2_run: Path) -> None:
    pdf, svg = tmp_path / "arm.pdf", tmp_path / "arm.svg"
    for out in (pdf, svg):
        result = run("render", "--from", str(fig2_run), "--time", "1", "-o", str(out))
        assert result.exit_code == 0, result.output
        assert "vector" in result.output
    data = pdf.read_bytes()
    assert data.startswith(b"%PDF-") and data.rstrip().endswith(b"%%EOF")
    root = ET.parse(svg).getroot()
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    # the legend's words are in the drawing (as glyph paths with their text kept as ids or
    # comments, or as text): the SVG names the axes colours' entries
    text = svg.read_text(encoding="utf-8")
    assert "x axis" in text and "DH frames" in text
    # tight bounds: the vector picture is cropped to the drawing, smaller than the 10 x 8 in page
    width = float(root.get("width", "0pt").removesuffix("pt"))
    assert 0 < width < 720


def test_plot_writes_pdf_and_svg(tmp_path: Path, fig2_run: Path) -> None:
    for suffix in ("pdf", "svg"):
        out = tmp_path / f"signals.{suffix}"
        assert run("plot", str(fig2_run), "--imu", "imu_tool", "-o", str(out)).exit_code == 0
    assert (tmp_path / "signals.pdf").read_bytes().startswith(b"%PDF-")
    ET.parse(tmp_path / "signals.svg")


def test_frame_axes_are_red_green_blue_for_x_y_z_with_a_legend() -> None:
    from aaria_pin.viz._plotting import pyplot
    from aaria_pin.viz.render import draw_geometry, draw_legend

    scene, poses = preset_view("aaria-fig2")
    geometry = posed_geometry(scene, poses)
    assert geometry.segment_rgb is not None and geometry.origins is not None
    # every frame's three segments: red, green, blue; for the frames drawn at their own
    # origin (world, tool, IMUs), along the frame's x, y, z axes in the world
    start = 0
    for item in scene.lines:
        segments = geometry.segments[start : start + 3]
        np.testing.assert_allclose(geometry.segment_rgb[start : start + 3], AXIS_COLOURS)
        start += len(item.points)
        if item.role == "dh_frame":
            continue  # drawn at the link's end, not at its frame's origin
        R = poses[scene.frames.index(item.frame)][:3, :3]
        direction = segments[:, 1] - segments[:, 0]
        direction /= np.linalg.norm(direction, axis=1, keepdims=True)
        np.testing.assert_allclose(direction, R.T, atol=1e-9)  # row k: the frame's axis k
    plt = pyplot()
    figure = plt.figure()
    try:
        axes = figure.add_subplot(projection="3d", computed_zorder=False)
        draw_geometry(axes, geometry)
        legend = draw_legend(axes, geometry)
        labels = [t.get_text() for t in legend.get_texts()]
        assert {"x axis", "y axis", "z axis", "DH frames", "IMUs", "tool frame"} <= set(labels)
        # equal scales: the three axes span the same length
        spans = [np.ptp(limits) for limits in (axes.get_xlim(), axes.get_ylim(), axes.get_zlim())]
        np.testing.assert_allclose(spans, spans[0])
    finally:
        plt.close(figure)


def test_rms_bars_equal_the_printed_rms_side_by_side(tmp_path: Path, fig2_run: Path) -> None:
    from aaria_pin.viz._plotting import pyplot
    from aaria_pin.viz.report_plots import TORQUE_BARS, draw_torque_report

    out = tmp_path / "torques.svg"
    result = run("torques", str(fig2_run), "--json", "--plot", str(out))
    assert result.exit_code == 0, result.output
    ET.parse(out)
    report = json.loads(result.output)
    # the printed RMS is the RMS of the stored torques (an independent computation)
    tau = np.asarray(read_run(fig2_run).tau, dtype=float)
    for joint in report["joints"]:
        column = tau[:, joint["module"] - 1]
        assert joint["rms"] == pytest.approx(np.sqrt(np.mean(column**2)), rel=1e-12)
    # stacking would mislead: the terms' RMS add up to more than tau's RMS on some joint
    assert any(sum(j["rms_terms"].values()) > 1.05 * j["rms"] for j in report["joints"])
    plt = pyplot()
    figure = plt.figure()
    try:
        grid = draw_torque_report(figure, report, "t")
        units = list(dict.fromkeys(j["unit"] for j in report["joints"]))
        assert len(grid) == len(units) == 2  # N·m and N apart
        for axes, unit in zip(grid, units, strict=True):
            joints = [j for j in report["joints"] if j["unit"] == unit]
            containers = {c.get_label(): c for c in axes.containers}
            for key, label, _ in TORQUE_BARS:
                bars = containers[label].patches
                printed = [j["rms"] if key == "rms" else j["rms_terms"][key] for j in joints]
                np.testing.assert_allclose([b.get_height() for b in bars], printed, rtol=1e-12)
                assert all(b.get_y() == 0.0 for b in bars)  # side by side, none stacked
    finally:
        plt.close(figure)
    # the table prints the same RMS values
    text = run("torques", str(fig2_run)).output
    first = report["joints"][0]
    for value in (first["rms"], *first["rms_terms"].values()):
        assert f"{value:.4g}" in text


def test_workspace_plot_has_equal_axes(tmp_path: Path) -> None:
    from aaria_pin.apps.wrist.wrist_kinematics import wrist_workspace
    from aaria_pin.viz._plotting import pyplot
    from aaria_pin.viz.report_plots import draw_workspace, plot_workspace

    workspace = wrist_workspace(samples=3000)
    plt = pyplot()
    figure = plt.figure()
    try:
        axes = figure.add_subplot(projection="3d")
        draw_workspace(axes, workspace, "w")
        spans = [np.ptp(limits) for limits in (axes.get_xlim(), axes.get_ylim(), axes.get_zlim())]
        np.testing.assert_allclose(spans, spans[0])
        extent = np.ptp(workspace.points, axis=0).max()
        assert spans[0] == pytest.approx(1.05 * extent)  # tight: 5 % margin
    finally:
        plt.close(figure)
    assert plot_workspace(workspace, tmp_path / "w.pdf").read_bytes().startswith(b"%PDF-")


def test_animation_has_the_asked_size_and_frame_rate(tmp_path: Path) -> None:
    from PIL import Image

    from aaria_pin.apps.arm.run import simulate_pick_place
    from aaria_pin.apps.arm.task import Cylinder
    from aaria_pin.errors import ParameterError
    from aaria_pin.viz.arm_pictures import write_animation

    arm_run = simulate_pick_place(Cylinder(0.3, 0.1, 0.03, 0.12, 0.5), (0.1, 0.3), rate=20.0)
    path = write_animation(tmp_path / "a.gif", arm_run, fps=2, size=160)
    with Image.open(path) as image:
        assert image.size == (160, 160)
        assert image.info["duration"] == 500  # ms a frame: 2 frames per second
        assert image.n_frames == int(np.ceil(arm_run.path.time[-1] * 2))
    with pytest.raises(ParameterError, match="size"):
        write_animation(tmp_path / "b.gif", arm_run, size=20)
    assert not (tmp_path / "b.gif").exists()


def test_a_vector_figure_written_twice_is_the_same_file(tmp_path: Path) -> None:
    for suffix in ("svg", "pdf"):
        first, second = tmp_path / f"a.{suffix}", tmp_path / f"b.{suffix}"
        for out in (first, second):
            result = run("render", "--preset", "aaria-fig2", "-o", str(out))
            assert result.exit_code == 0, result.output
        assert first.read_bytes() == second.read_bytes(), suffix
