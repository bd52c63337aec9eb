"""Plug-ins of the viewers: run kinds and presets of applications, imported on first look-up."""

from __future__ import annotations

import sys
import textwrap
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

from aaria_pin.core.catalogue import find_robot
from aaria_pin.core.urdf_robot import read_urdf_file
from aaria_pin.core.urdf_run import simulate_urdf_run
from aaria_pin.errors import InputFileError, ModelError, ParameterError
from aaria_pin.files.runfile import write_run
from aaria_pin.viz import sources

PLUGIN = "aaria_test_view_plugin"

PLUGIN_SOURCE = '''
"""A dummy plug-in: claims every run file the model kind would, and offers a preset."""

from aaria_pin.aaria.presets import get_preset
from aaria_pin.files.runfile import is_run_file
from aaria_pin.viz.sources import register_run_kind, table_view
from aaria_pin.viz._model_source import load_model_run

IMPORTS = []
IMPORTS.append(1)


def load(path):
    view = load_model_run(path)
    return type(view)("dummy: " + view.title, "dummy", view.scene, view.signals, view.frame_poses)


register_run_kind("dummy", is_run_file, load)


def build():
    preset = get_preset("spherical-wrist")
    scene, poses = table_view(preset.table, preset.convention, "dummy-arm")
    return scene, poses


def broken():
    scene, poses = build()
    return scene, poses[:-1]


PRESETS = {"dummy-arm": build, "broken-arm": broken}
'''


@pytest.fixture
def plugin(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[str]:
    """A plug-in module on sys.path, named as the only plug-in; the registry restored after."""
    (tmp_path / f"{PLUGIN}.py").write_text(textwrap.dedent(PLUGIN_SOURCE), encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    isolate(monkeypatch, (PLUGIN,))
    yield PLUGIN
    sys.modules.pop(PLUGIN, None)


def isolate(monkeypatch: pytest.MonkeyPatch, plugins: tuple[str, ...]) -> None:
    """Name the plug-ins, with the built-in kinds only and no preset (plug-ins not loaded)."""
    monkeypatch.setattr(sources, "_PLUGINS", plugins)
    built_in = {k: v for k, v in sources._KINDS.items() if k in ("aaria", "wrist")}
    monkeypatch.setattr(sources, "_KINDS", built_in)  # without any plug-in's kind
    monkeypatch.setattr(sources, "_FALLBACK_KINDS", dict(sources._FALLBACK_KINDS))
    monkeypatch.setattr(sources, "_PRESETS", {})
    monkeypatch.setattr(sources, "_plugins_loaded", False)


@pytest.fixture(scope="module")
def ur5_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    entry = find_robot("ur5")
    record = simulate_urdf_run(
        read_urdf_file(entry.urdf), urdf_dir=entry.urdf.parent, duration=0.5, rate=20.0
    )
    return write_run(tmp_path_factory.mktemp("ur5") / "ur5.h5", record)


def test_a_plugin_is_imported_on_first_look_up_and_tried_before_the_model_kind(
    plugin: str, ur5_run: Path
) -> None:
    assert plugin not in sys.modules  # not on import of the viewers
    assert sources.run_kind(ur5_run) == "dummy"  # before the model kind, registered earlier
    module = sys.modules[plugin]
    view = sources.load_run_view(ur5_run)
    assert view.kind == "dummy" and view.title == "dummy: ur5.h5"
    assert view.frame_poses(np.array([0])).shape == (1, len(view.scene.frames), 4, 4)
    sources.run_kind(ur5_run)
    assert module.IMPORTS == [1]  # imported once


def test_without_the_plugin_a_urdf_run_is_of_the_model_kind(
    monkeypatch: pytest.MonkeyPatch, ur5_run: Path
) -> None:
    isolate(monkeypatch, ("aaria_pin_no_such_plugin", "aaria_pin.no_such_module"))
    assert sources.run_kind(ur5_run) == "model"
    assert sources.preset_names() == ("aaria-fig2", "aaria-fig3", "spherical-wrist")


def test_a_plugin_that_misses_a_module_of_its_own_package_is_an_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, ur5_run: Path
) -> None:
    """A missing plug-in is left out; a broken one (it imports what is not there) is not."""
    (tmp_path / "aaria_test_broken_plugin.py").write_text("import aaria_pin.not_there\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    isolate(monkeypatch, ("aaria_test_broken_plugin",))
    try:
        with pytest.raises(ModuleNotFoundError, match=r"aaria_pin\.not_there"):
            sources.run_kind(ur5_run)
    finally:
        sys.modules.pop("aaria_test_broken_plugin", None)


def test_plugin_presets_are_drawn_beside_the_table_presets(plugin: str) -> None:
    names = sources.preset_names()
    assert names[:3] == ("aaria-fig2", "aaria-fig3", "spherical-wrist")
    assert set(names[3:]) == {"dummy-arm", "broken-arm"}
    scene, poses = sources.preset_view("dummy-arm")
    assert scene.name == "dummy-arm" and poses.shape == (len(scene.frames), 4, 4)
    table_scene, table_poses = sources.preset_view("spherical-wrist")
    assert np.allclose(table_poses, poses) and table_scene.frames == scene.frames
    with pytest.raises(ModelError, match="broken-arm"):
        sources.preset_view("broken-arm")
    with pytest.raises(ParameterError, match=r"not known; allowed: .*dummy-arm"):
        sources.preset_view("nope")


def test_an_announced_model_preset_is_a_clear_error_until_its_plugin_gives_it(
    plugin: str,
) -> None:
    with pytest.raises(ParameterError) as caught:
        sources.preset_view("pick-place-arm")
    message = str(caught.value)
    assert "model preset" in message and "aaria_pin.viz._arm_source" in message
    assert "allowed: aaria-fig2, aaria-fig3, spherical-wrist, " in message
    assert "dummy-arm" in message and "\n" not in message


def test_unknown_files_name_the_plugin_kinds_too(plugin: str, tmp_path: Path) -> None:
    other = tmp_path / "other.txt"
    other.write_text("x")
    with pytest.raises(InputFileError, match="allowed: aaria, wrist, dummy, model run files"):
        sources.run_kind(other)


def test_a_record_in_memory_and_a_data_set_run_are_drawn_as_their_files(
    tmp_path: Path, ur5_run: Path
) -> None:
    """record_view draws a record without a file; a data set's run is drawn through the reader."""
    from aaria_pin.files.runfile import read_run

    record = read_run(ur5_run)
    from_file = sources.load_run_view(ur5_run)
    in_memory = sources.record_view(record, "ur5 in memory")
    assert in_memory.kind == from_file.kind == "model" and in_memory.title == "ur5 in memory"
    samples = np.arange(from_file.time.size)
    np.testing.assert_array_equal(in_memory.frame_poses(samples), from_file.frame_poses(samples))
    tool = from_file.frame_poses(samples)[:, from_file.scene.frames.index("tool0")]
    np.testing.assert_allclose(tool, record.tool_pose, atol=1e-9)
    with pytest.raises(ParameterError, match=r"run is for a data set; .* is a run file") as bad:
        sources.load_run_view(ur5_run, run=1)
    assert bad.value.parameter == "run"
    dataset = Path(__file__).parents[1] / "fixtures" / "v0_1_0" / "ur5_dataset.h5"
    view = sources.load_run_view(dataset, run=1)
    assert view.kind == "model" and view.title == "ur5_dataset.h5 run 1"
    import h5py

    with h5py.File(dataset, "r") as handle:
        stored_q = handle["q"][1]
    np.testing.assert_array_equal(view.signals.q, stored_q.astype(float))
