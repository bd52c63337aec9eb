"""The self-contained HTML viewer: its page, and the page opened in headless Chromium."""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import aaria_pin.viz
from aaria_pin.aaria.presets import get_preset
from aaria_pin.aaria.simulate import simulate_run
from aaria_pin.apps.wrist.run import simulate_wrist, write_wrist_run
from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.urdf_robot import read_urdf_file
from aaria_pin.core.urdf_run import simulate_urdf_run
from aaria_pin.errors import ParameterError
from aaria_pin.files.runfile import write_run
from aaria_pin.viz.html import shown_samples, signal_panels, viewer_html, write_viewer
from aaria_pin.viz.plot import Panel
from aaria_pin.viz.sources import load_run_view

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


@pytest.fixture(scope="module")
def pages(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("pages")
    record = simulate_run(get_preset("aaria-fig2").table, duration=4.0, rate=50.0)
    wrist = simulate_wrist(np.radians([90.0, 60.0, -45.0]), start=0.2, rate=50.0)
    robot = find_robot("ur5")
    ur5 = simulate_urdf_run(
        read_urdf_file(robot.urdf),
        urdf_dir=robot.urdf.parent,
        source="ur5",
        duration=4.0,
        rate=50.0,
    )
    out = {}
    for name, run_file in (
        ("aaria", write_run(folder / "fig2.h5", record)),
        ("wrist", write_wrist_run(folder / "wrist.h5", wrist)),
        ("model", write_run(folder / "ur5.h5", ur5)),
    ):
        view = load_run_view(run_file)
        assert view.kind == name
        k = shown_samples(view.time.size, 120)
        out[name] = write_viewer(
            folder / f"{name}.html",
            view.scene,
            view.time[k],
            view.frame_poses(k),
            view.title,
            signal_panels(view.signals, k),
        )
    return out


def embedded(page: str) -> dict:
    match = re.search(r'<script type="application/json" id="data">(.*?)</script>', page, re.S)
    assert match
    return json.loads(match.group(1))


def test_page_embeds_the_run_and_loads_nothing(pages: dict[str, Path]) -> None:
    page = pages["aaria"].read_text(encoding="utf-8")
    data = embedded(page)
    assert len(data["times"]) == 120 and data["times"][0] == 0.0 and data["times"][-1] == 4.0
    assert len(data["poses"]) == 120 and len(data["poses"][0]) == 12 * len(data["frames"])
    assert data["frames"][0] == "world" and "tool_tip" in data["frames"]
    assert {"slider", "play", "canvas"} <= set(re.findall(r'id="(\w+)"', page))
    assert 'type="range"' in page
    # offline: the library is inlined, no address to fetch outside it, a policy that forbids
    # any load
    library = (Path(aaria_pin.viz.__file__).parent / "vendor" / "three-r147.min.js").read_text()
    assert library in page
    ours = page.replace(library, "")
    assert "http://" not in ours and "https://" not in ours
    assert not re.search(r"<(script|link|img|iframe)[^>]*(src|href)=", page)
    assert "default-src 'none'" in page


def test_samples_are_decimated_evenly_and_keep_both_ends() -> None:
    k = shown_samples(1001, 100)
    assert k[0] == 0 and k[-1] == 1000 and len(k) == 100
    assert np.ptp(np.diff(k)) <= 1
    assert np.array_equal(shown_samples(50, 100), np.arange(50))
    with pytest.raises(ParameterError):
        shown_samples(10, 1)


def test_title_and_data_cannot_break_out_of_the_page(pages: dict[str, Path]) -> None:
    from aaria_pin.viz.scene import Scene

    scene = Scene("x", ("world",))
    page = viewer_html(scene, np.zeros(1), np.eye(4)[None, None], "</script><b>")
    assert "</script><b>" not in page and "&lt;/script&gt;&lt;b&gt;" in page
    assert embedded(page)["title"] == "</script><b>"


def test_placeholders_in_the_title_or_the_data_are_left_alone() -> None:
    """The title is put in first and the data after it: neither is scanned for the other."""
    from aaria_pin.viz.scene import Scene, triad

    title = "__AARIA_TITLE__ & __AARIA_DATA__"
    scene = Scene(
        "x", ("world", "__AARIA_TITLE__"), lines=(triad("__AARIA_TITLE__", 0.1, "other"),)
    )
    page = viewer_html(scene, np.zeros(1), np.stack([np.eye(4)] * 2)[None], title)
    data = embedded(page)
    assert data["title"] == title and data["frames"] == ["world", "__AARIA_TITLE__"]
    shown = "&#95;&#95;AARIA&#95;TITLE&#95;&#95; &amp; &#95;&#95;AARIA&#95;DATA&#95;&#95;"
    assert f"<title>{shown}</title>" in page and f'<h1 id="title">{shown}</h1>' in page
    assert page.count('id="data"') == 1


# --- in the browser -------------------------------------------------------------------------


def chromium(tmp: Path, url: str, *extra: str) -> subprocess.CompletedProcess[str]:
    """Headless Chromium with networking off (a dead proxy for everything, loopback too)."""
    assert CHROMIUM
    command = [
        CHROMIUM,
        "--headless",
        "--no-sandbox",
        "--use-angle=swiftshader",  # WebGL in software, as a machine without a GPU has it
        "--enable-unsafe-swiftshader",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--disable-extensions",
        f"--user-data-dir={tmp / 'profile'}",
        "--proxy-server=127.0.0.1:9",
        "--proxy-bypass-list=<-loopback>",
        "--enable-logging=stderr",
        "--v=0",
        "--window-size=900,700",
        "--virtual-time-budget=3000",
        *extra,
        url,
    ]
    return subprocess.run(command, capture_output=True, text=True, timeout=120, check=False)


def console_lines(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if ":CONSOLE" in line]


def status(dom: str) -> dict[str, str]:
    match = re.search(r'<span id="status"([^>]*)>([^<]*)<', dom)
    assert match, dom[:500]
    attributes = dict(re.findall(r'([\w-]+)="([^"]*)"', match.group(1)))
    return {**attributes, "text": match.group(2)}


def canvas_pixels(path: Path) -> np.ndarray:
    from PIL import Image

    with Image.open(path) as image:
        pixels = np.asarray(image.convert("RGB"), dtype=int)
    return pixels[80:620, :520]  # the 3D view: between the header and the controls


needs_chromium = pytest.mark.skipif(
    CHROMIUM is None and not os.environ.get("CI"),
    reason="chromium is not installed (.ci/run installs it on CI, where this test must run)",
)


@needs_chromium
@pytest.mark.slow
def test_console_check_catches_a_broken_page(tmp_path: Path) -> None:
    """The console check below can fail: a page that throws shows up on it."""
    broken = tmp_path / "broken.html"
    broken.write_text("<html><body><script>notDefined();</script></body></html>")
    result = chromium(tmp_path, broken.as_uri(), "--dump-dom")
    assert any("Uncaught ReferenceError" in line for line in console_lines(result.stderr))


@needs_chromium
@pytest.mark.slow
@pytest.mark.parametrize("name", ["aaria", "wrist", "model"])
def test_page_runs_in_chromium_and_the_slider_moves_the_arm(
    tmp_path: Path, pages: dict[str, Path], name: str
) -> None:
    url = pages[name].as_uri()
    data = embedded(pages[name].read_text(encoding="utf-8"))
    reports = {}
    for t in (1.0, 3.0):
        dom = chromium(tmp_path, f"{url}#t={t:g}", "--dump-dom")
        assert dom.returncode == 0, dom.stderr[-2000:]
        assert console_lines(dom.stderr) == []  # no error, no warning, nothing logged at all
        report = status(dom.stdout)
        assert report["data-state"] == "ready", report
        assert int(report["data-inked"]) > 2000  # the view is drawn on
        k = int(np.argmin(np.abs(np.array(data["times"]) - t)))
        assert int(report["data-sample"]) == k
        reports[t] = report
    # every triangle of the solids is drawn by WebGL (meshes, not only lines)
    triangles = sum(len(solid["t"]) // 3 for solid in data["solids"])
    assert int(reports[1.0]["data-triangles"]) == triangles > 100
    # the signal panel follows the playback: its cursor moves right with the time, by the
    # time's share of the plot's width (between 1 s and 3 s of a 4 s run: half of it)
    assert int(reports[1.0]["data-panels"]) == len(data["panels"]) > 0
    x1, x3 = float(reports[1.0]["data-cursor"]), float(reports[3.0]["data-cursor"])
    assert x3 > x1 > 0

    shots = []
    for t in (0.0, 3.0):
        shot = tmp_path / f"shot_{t}.png"
        result = chromium(tmp_path, f"{url}#t={t}", f"--screenshot={shot}")
        assert result.returncode == 0 and shot.is_file(), result.stderr[-2000:]
        assert console_lines(result.stderr) == []
        shots.append(canvas_pixels(shot))
    for pixels in shots:
        assert np.count_nonzero(pixels.min(axis=-1) < 200) > 2000  # not blank
    changed = np.count_nonzero(np.abs(shots[0] - shots[1]).max(axis=-1) > 30)
    assert changed > 300  # the arm moved with the slider


def test_ur5_page_holds_its_urdf_meshes_and_signals(pages: dict[str, Path]) -> None:
    """The UR5's page draws each link's visual mesh (decimated), in the .dae's own colours."""
    data = embedded(pages["model"].read_text(encoding="utf-8"))
    links = ("base_link", "shoulder_link", "upper_arm_link", "forearm_link", "wrist_1_link")
    meshed = {data["frames"][solid["f"]] for solid in data["solids"]}
    assert set(links) <= meshed
    triangles = sum(len(solid["t"]) // 3 for solid in data["solids"])
    assert 10_000 < triangles < 45_000  # 95 000 in the files, decimated to about 30 000
    assert not data["bones"]  # no stick figure where the robot has its meshes
    # the UR5's .dae parts are dark grey and blue-grey, not the "link" role's blue
    colours = {tuple(solid["c"]) for solid in data["solids"]}
    assert len(colours) > 3 and all(max(c) - min(c) < 0.25 for c in colours)
    # one IMU's six signals and the torques, at the page's samples
    groups = {panel["group"] for panel in data["panels"]}
    assert "imu_tool" in groups and "" in groups
    (torques,) = [panel for panel in data["panels"] if panel["group"] == ""]
    assert torques["labels"][0] == "shoulder_pan_joint" and "torque [N·m]" in torques["title"]
    assert len(torques["labels"]) == 6 and len(torques["values"][0]) == len(data["times"])
    gyro = next(p for p in data["panels"] if p["group"] == "imu_tool")
    assert "gyroscope" in gyro["title"] and gyro["labels"] == ["wx", "wy", "wz"]


def test_panels_of_the_wrong_length_are_refused() -> None:
    from aaria_pin.viz.scene import Scene

    panel = Panel("x", "x [m]", np.zeros((3, 1)), ("a",))
    with pytest.raises(ParameterError, match="panels") as error:
        viewer_html(
            Scene("x", ("world",)), np.zeros(2), np.stack([np.eye(4)[None]] * 2), "t", [panel]
        )
    assert error.value.allowed == "(samples, labels) = (2, 1)"
    with pytest.raises(ParameterError, match="poses of shape") as error:
        viewer_html(Scene("x", ("world",)), np.zeros(2), np.stack([np.eye(4)[None]] * 3), "t")
    assert error.value.parameter == "poses"


def test_write_run_viewer_decimates_the_run(tmp_path: Path) -> None:
    from aaria_pin.viz.html import write_run_viewer

    record = simulate_run(get_preset("aaria-fig2").table, duration=1.0, rate=50.0)
    run = write_run(tmp_path / "run.h5", record)
    shown, samples = write_run_viewer(run, tmp_path / "v.html", max_samples=20)
    assert (shown, samples) == (20, 51) and "<canvas" in (tmp_path / "v.html").read_text()
    assert write_run_viewer(run, tmp_path / "all.html", max_samples=100) == (51, 51)
    with pytest.raises(ParameterError) as caught:
        write_run_viewer(run, tmp_path / "x.html", max_samples=1)
    assert caught.value.parameter == "max_samples"
