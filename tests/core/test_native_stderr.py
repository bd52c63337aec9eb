"""Native output captured: what C and C++ code writes to fd 2 is folded into our one line."""

from __future__ import annotations

import ctypes
import os
import subprocess
import sys
from pathlib import Path

import pytest

from aaria_pin.core.model import build_model
from aaria_pin.core.native_stderr import CapturedText, captured_stderr
from aaria_pin.errors import ModelError

_URDFDOM = """Error:   material 'm' is not unique.
         at line 159 in /project/urdfdom/urdf_parser/src/model.cpp
Error:   Could not parse visual element for Link [arm]
         at line 537 in /project/urdfdom/urdf_parser/src/link.cpp
"""

_ROBOT = """<robot name="r"{version}>{materials}
  <link name="base"/>
  <link name="arm"><inertial><mass value="1"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
</robot>"""
_MATERIAL = '<material name="m"><color rgba="1 0 0 1"/></material>'
_REJECTED = {
    "twice": (_ROBOT.format(version="", materials=_MATERIAL * 2), "material 'm' is not unique"),
    "version": (_ROBOT.format(version=' version="3.0"', materials=""), "Invalid 'version'"),
}
"""URDFs our parser passes and urdfdom refuses, with what urdfdom says of them."""


def test_folded_drops_source_places_and_joins_messages() -> None:
    assert CapturedText(_URDFDOM).folded() == (
        "material 'm' is not unique; Could not parse visual element for Link [arm]"
    )
    assert CapturedText("").folded() == ""


def test_writes_to_fd_2_are_captured_and_fd_2_restored(capfd: pytest.CaptureFixture[str]) -> None:
    libc = ctypes.CDLL(None)
    before = os.fstat(2)
    with captured_stderr() as printed:
        os.write(2, b"from python's fd\n")
        libc.write(2, b"from C\n", 7)
    assert printed.text == "from python's fd\nfrom C\n"
    after = os.fstat(2)
    assert (after.st_dev, after.st_ino) == (before.st_dev, before.st_ino)
    os.write(2, b"after\n")
    assert capfd.readouterr().err == "after\n"


def test_fd_2_is_restored_when_the_block_raises(capfd: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(KeyError), captured_stderr() as printed:
        os.write(2, b"said\n")
        raise KeyError("boom")
    assert printed.text == "said\n"
    os.write(2, b"after\n")
    assert capfd.readouterr().err == "after\n"


@pytest.mark.parametrize("case", sorted(_REJECTED))
def test_build_model_names_what_urdfdom_said(case: str, capfd: pytest.CaptureFixture[str]) -> None:
    text, said = _REJECTED[case]
    with pytest.raises(ModelError, match=f"urdfdom: {said}") as caught:
        build_model(text)
    assert "\n" not in str(caught.value)
    assert "model.cpp" not in str(caught.value)
    assert capfd.readouterr().err == ""


@pytest.mark.parametrize("command", ["simulate", "mjcf"])
def test_the_command_prints_one_line_only(command: str, tmp_path: Path) -> None:
    urdf = tmp_path / "bad.urdf"
    urdf.write_text(_REJECTED["twice"][0], encoding="utf-8")
    output = tmp_path / ("run.h5" if command == "simulate" else "robot.xml")
    result = subprocess.run(
        [sys.executable, "-m", "aaria_pin.cli", command, "--urdf", str(urdf), "-o", str(output)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1, result.stderr
    assert result.stderr.startswith("aaria: error: URDF is not valid (urdfdom: material 'm'")
    assert not output.exists()


def test_threads_take_turns_and_nested_blocks_capture_their_own(
    capfd: pytest.CaptureFixture[str],
) -> None:
    import threading

    texts: list[str] = []

    def capture(number: int) -> None:
        with captured_stderr() as printed:
            os.write(2, f"thread {number}\n".encode())
        texts.append(printed.text)

    threads = [threading.Thread(target=capture, args=(n,)) for n in range(8)]
    with captured_stderr() as outer:
        os.write(2, b"outer\n")
        with captured_stderr() as inner:
            os.write(2, b"inner\n")
        for thread in threads:
            thread.start()
    for thread in threads:
        thread.join()
    assert (outer.text, inner.text) == ("outer\n", "inner\n")
    assert sorted(texts) == [f"thread {n}\n" for n in range(8)]
    os.write(2, b"after\n")
    assert capfd.readouterr().err == "after\n"
