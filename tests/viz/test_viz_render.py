"""PNG pictures: an arm in the paper's colours, and a run's signal panels."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.errors import ParameterError
from aaria_pin.files.runfile import write_run
from aaria_pin.viz._figure import figure_file
from aaria_pin.viz.plot import Panel, plot_panels, signal_panels
from aaria_pin.viz.render import render_geometry
from aaria_pin.viz.scene import COLOURS, posed_geometry
from aaria_pin.viz.sources import Signals, load_run_view, table_view


def read_png(path: Path) -> np.ndarray:
    from PIL import Image

    with Image.open(path) as image:
        return np.asarray(image.convert("RGB"), dtype=float) / 255.0


def colour_pixels(image: np.ndarray, colour: tuple[float, float, float]) -> int:
    """Pixels that are the colour at 50–100 % brightness (faces are shaded), within 0.08."""
    c = np.asarray(colour)
    scale = image @ c / (c @ c)
    residual = np.linalg.norm(image - scale[..., None] * c, axis=-1)
    return int(np.count_nonzero((residual < 0.08) & (scale > 0.5) & (scale < 1.05)))


def scheme_counts(image: np.ndarray) -> dict[str, int]:
    names = {
        "green": "joint",
        "blue": "link",
        "red": "dh_frame",
        "yellow": "tool_frame",
        "purple": "imu_frame",
    }
    return {name: colour_pixels(image, COLOURS[role]) for name, role in names.items()}


@pytest.mark.parametrize("name", ["aaria-fig2", "aaria-fig3", "spherical-wrist"])
def test_preset_picture_has_the_size_and_the_paper_colours(tmp_path: Path, name: str) -> None:
    preset = get_preset(name)
    scene, poses = table_view(preset.table, preset.convention, name)
    path = render_geometry(
        posed_geometry(scene, poses), tmp_path / "arm.png", name, width=640, height=480
    )
    image = read_png(path)
    assert image.shape == (480, 640, 3)
    assert np.count_nonzero(image.min(axis=-1) < 0.9) > 2000  # not blank
    counts = scheme_counts(image)
    for colour in ("green", "blue", "red", "yellow", "purple"):
        assert counts[colour] >= 15, counts


def test_colour_check_fails_on_a_picture_without_the_scheme(tmp_path: Path) -> None:
    """The pixel test can fail: a picture of only grey faces has none of the scheme's colours."""
    preset = get_preset("aaria-fig2")
    scene, poses = table_view(preset.table, preset.convention, "grey")
    geometry = posed_geometry(scene, poses)
    grey = type(geometry)(
        geometry.faces,
        tuple("other" for _ in geometry.face_roles),
        geometry.segments,
        tuple("other" for _ in geometry.segment_roles),
        geometry.segment_widths,
    )
    image = read_png(render_geometry(grey, tmp_path / "grey.png", "", width=400, height=300))
    counts = scheme_counts(image)
    assert max(counts[c] for c in ("green", "red", "yellow", "purple")) < 15, counts


def test_bad_sizes_write_nothing(tmp_path: Path) -> None:
    preset = get_preset("aaria-fig2")
    scene, poses = table_view(preset.table, preset.convention, "x")
    with pytest.raises(ParameterError, match="allowed: 100 to"):
        render_geometry(posed_geometry(scene, poses), tmp_path / "a.png", "x", width=50)
    assert list(tmp_path.iterdir()) == []


@pytest.fixture(scope="module")
def run_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    record = simulate_run(get_preset("aaria-fig2").table, duration=2.0, rate=50.0)
    return write_run(tmp_path_factory.mktemp("run") / "run.h5", record)


def test_signal_panels_cover_joints_torques_wrench_and_every_imu(run_file: Path) -> None:
    view = load_run_view(run_file)
    panels = signal_panels(view.signals)
    # fig2: four revolute joints and two prismatic ones, a row of panels for each kind
    assert len(panels) == 2 + 2 + 2 + 2 * 14
    units = [panel.ylabel for panel in panels]
    assert units[:4] == ["angle [rad]", "torque [N·m]", "position [m]", "force [N]"]
    assert units[4:6] == ["force [N]", "moment [N·m]"]
    assert units.count("angular velocity [rad/s]") == 14
    assert units.count("specific force [m/s²]") == 14
    kinds = np.array(view.signals.kinds)
    assert list(kinds) == ["prismatic", "revolute", "revolute", "revolute", "prismatic", "revolute"]
    assert np.array_equal(panels[1].values, view.signals.tau[:, kinds == "revolute"])
    assert np.array_equal(panels[3].values, view.signals.tau[:, kinds == "prismatic"])
    assert panels[1].labels == ("tau2", "tau3", "tau4", "tau6")  # the unit is the y label's
    assert panels[3].labels == ("f1", "f5")
    one = signal_panels(view.signals, "imu_link3_b")
    assert [p.title for p in one[6:]] == ["imu_link3_b: gyroscope", "imu_link3_b: accelerometer"]
    assert np.array_equal(one[6].values, view.signals.imus["imu_link3_b"][:, :3])
    with pytest.raises(ParameterError, match="imu_link3_b"):
        signal_panels(view.signals, "imu_nowhere")


def test_a_large_force_does_not_share_an_axis_with_small_torques() -> None:
    """The pick-and-place case: an 85 N lift and 2 N·m torques go to separate panels."""
    time = np.linspace(0.0, 1.0, 11)
    tau = np.column_stack([85.0 + time, 2.0 * np.sin(time), -2.0 * time])
    q = np.zeros_like(tau)
    for kinds in ((), ("prismatic", "revolute", "revolute")):  # told by units, or given
        signals = Signals(
            time, q, ("lift [m]", "a [rad]", "b [rad]"), tau, ("lift [N]", "a [N·m]", "b [N·m]"),
            joint_kinds=kinds,
        )  # fmt: skip
        panels = signal_panels(signals)
        assert [p.ylabel for p in panels] == [
            "angle [rad]", "torque [N·m]", "position [m]", "force [N]"
        ]  # fmt: skip
        assert np.abs(panels[1].values).max() <= 2.0 and panels[1].labels == ("a", "b")
        assert np.array_equal(panels[3].values, tau[:, :1]) and panels[3].labels == ("lift",)
    only_revolute = Signals(time, q[:, 1:], ("a [rad]", "b [rad]"), tau[:, 1:], ("a", "b"),
                            joint_kinds=("revolute", "revolute"))  # fmt: skip
    assert len(signal_panels(only_revolute)) == 2


def test_panels_whose_labels_do_not_match_their_traces_are_refused(tmp_path: Path) -> None:
    time = np.linspace(0.0, 1.0, 5)
    panel = Panel("p", "x [m]", np.zeros((5, 2)), ("a", "b", "c"))
    with pytest.raises(ParameterError, match="labels"):
        plot_panels(time, [panel], tmp_path / "p.png", "p")
    assert list(tmp_path.iterdir()) == []


def test_signal_png_has_one_row_of_panels_per_pair(tmp_path: Path, run_file: Path) -> None:
    view = load_run_view(run_file)
    panels = signal_panels(view.signals, "imu_tool")
    path = plot_panels(view.time, panels, tmp_path / "s.png", "run", width=1000, row_height=250)
    image = read_png(path)
    assert image.shape == (4 * 250, 1000, 3)
    # every panel draws coloured traces (matplotlib's default cycle is coloured, axes grey)
    saturation = image.max(axis=-1) - image.min(axis=-1)
    for row in range(4):
        for column in range(2):
            cell = saturation[row * 250 : (row + 1) * 250, column * 500 : (column + 1) * 500]
            assert np.count_nonzero(cell > 0.3) > 200, (row, column)


def drawn_figure(monkeypatch: pytest.MonkeyPatch, draw: Callable[[], object]) -> Any:
    """The figure ``draw`` saves, kept open (plot_panels closes it otherwise)."""
    import matplotlib.pyplot as plt

    before = set(plt.get_fignums())
    monkeypatch.setattr(plt, "close", lambda *args: None)
    draw()
    (number,) = set(plt.get_fignums()) - before
    figure = plt.figure(number)
    monkeypatch.undo()
    return figure


def overlaps(a: Any, b: Any) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def test_legends_sit_outside_their_panels_and_cover_no_title(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, run_file: Path
) -> None:
    import matplotlib.pyplot as plt

    view = load_run_view(run_file)
    panels = signal_panels(view.signals, "imu_tool")
    figure = drawn_figure(
        monkeypatch, lambda: plot_panels(view.time, panels, tmp_path / "l.png", "run")
    )
    try:
        renderer = figure.canvas.get_renderer()
        axes = [ax for ax in figure.axes if ax.get_visible()]
        assert len(axes) == len(panels)
        for ax in axes:
            legend = ax.get_legend().get_window_extent(renderer)
            for other in axes:
                assert not overlaps(legend, other.get_window_extent(renderer)), ax.get_title()
                assert not overlaps(legend, other.title.get_window_extent(renderer))
            assert legend.x1 <= figure.bbox.x1 + 1  # inside the picture
    finally:
        plt.close(figure)


def test_legend_check_catches_a_legend_inside_the_axes(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The overlap check above can fail: matplotlib's default legend place is inside."""
    import matplotlib.pyplot as plt

    time = np.linspace(0.0, 1.0, 5)

    def inside() -> None:
        with figure_file(tmp_path / "i.png", 400, 300) as figure:
            ax = figure.subplots()
            ax.plot(time, time, label="x")
            ax.legend()

    figure = drawn_figure(monkeypatch, inside)
    try:
        renderer = figure.canvas.get_renderer()
        ax = figure.axes[0]
        assert overlaps(ax.get_legend().get_window_extent(renderer), ax.get_window_extent(renderer))
    finally:
        plt.close(figure)


def test_render_picture_of_a_preset_a_table_file_and_a_run(tmp_path: Path, run_file: Path) -> None:
    from aaria_pin.viz.render import PictureSettings, render_picture

    settings = PictureSettings(width=320, height=240)
    title = render_picture(tmp_path / "p.png", preset="aaria-fig2", settings=settings)
    assert title == "aaria-fig2" and read_png(tmp_path / "p.png").shape == (240, 320, 3)
    table = tmp_path / "arm.csv"
    np.savetxt(table, get_preset("aaria-fig3").table, delimiter=",")
    title = render_picture(tmp_path / "t.png", dh_file=table, settings=settings)
    assert title == "arm.csv" and (tmp_path / "t.png").is_file()
    title = render_picture(tmp_path / "r.png", run_file=run_file, time=1.01, settings=settings)
    assert title == "run.h5, t = 1.000 s"  # the sample nearest 1.01 s at 50 Hz


@pytest.mark.parametrize(
    ("given", "parameter"),
    [({}, "preset"), ({"preset": "aaria-fig2", "dh_file": "x.csv"}, "preset"),
     ({"preset": "aaria-fig2", "time": 1.0}, "time"), ({"preset": "aaria-fig2", "run": 0}, "run")],
)  # fmt: skip
def test_render_picture_refuses_sources_that_do_not_fit(
    tmp_path: Path, given: dict[str, Any], parameter: str
) -> None:
    from aaria_pin.viz.render import render_picture

    with pytest.raises(ParameterError) as caught:
        render_picture(tmp_path / "p.png", **given)
    assert caught.value.parameter == parameter and list(tmp_path.iterdir()) == []


def test_plot_run_counts_panels_and_samples(tmp_path: Path, run_file: Path) -> None:
    from aaria_pin.viz.plot import plot_run

    view = load_run_view(run_file)
    panels, samples = plot_run(run_file, tmp_path / "p.png", width=800)
    assert samples == 101 and panels == len(signal_panels(view.signals))  # 2 s at 50 Hz
    assert read_png(tmp_path / "p.png").shape[1] == 800
    assert plot_run(run_file, tmp_path / "i.png", imu="imu_tool")[0] < panels
    with pytest.raises(ParameterError, match="width 10 px") as caught:
        plot_run(run_file, tmp_path / "w.png", width=10)
    assert caught.value.parameter == "width"
