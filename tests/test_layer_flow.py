"""``aaria simulate --preset aaria-fig2`` runs down the layers once: cli -> aaria (the table to a
robot) -> core (the run) -> files (the write, which pulls the run's pieces from the engine).

Traced call by call (``sys.setprofile``): a function of a lower layer calls into a higher layer
only through the robot-kind protocol the engine is given (``core.run.robot.RunRobot``: the DH
adapter's properties and its ``sines``, ``base``, ``record_columns``, ``attributes``); nothing
calls into the command line.
"""

from __future__ import annotations

import sys
from pathlib import Path
from types import FrameType
from typing import Any

from aaria_pin.cli import main
from aaria_pin.core.run.robot import RunRobot

ORDER = ("errors", "_version", "core", "files", "aaria", "apps", "viz", "cli")


def _layer(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if parts[0] == "aaria_pin" and len(parts) > 1 else None


def traced_calls(args: list[str]) -> list[tuple[str, str, str]]:
    """(caller's layer, callee's layer, callee module:function) of every call in the package."""
    calls: list[tuple[str, str, str]] = []

    def profile(frame: FrameType, event: str, arg: Any) -> None:
        if event != "call" or frame.f_back is None:
            return
        callee = _layer(frame.f_globals.get("__name__", ""))
        caller = _layer(frame.f_back.f_globals.get("__name__", ""))
        if callee in ORDER and caller in ORDER:
            name = f"{frame.f_globals['__name__']}:{frame.f_code.co_name}"
            calls.append((caller, callee, name))

    sys.setprofile(profile)
    try:
        main(args, standalone_mode=False)
    finally:
        sys.setprofile(None)
    return calls


def test_simulate_a_preset_runs_down_the_layers_once(tmp_path: Path) -> None:
    output = tmp_path / "run.h5"
    calls = traced_calls(
        ["simulate", "--preset", "aaria-fig2", "--duration", "0.1", "-o", str(output)]
    )
    assert output.is_file()
    steps = [(a, b) for a, b, name in calls if a != b and not name.endswith("<module>")]
    # the table becomes a robot (aaria) before the run is written (files pulls the pieces)
    assert steps.index(("cli", "aaria")) < steps.index(("cli", "files"))
    assert ("files", "core") in steps and not any(b == "cli" for _, b in steps)
    upward = {
        (caller, callee, name)
        for caller, callee, name in calls
        if ORDER.index(callee) > ORDER.index(caller)
    }
    protocol = {name for name in dir(RunRobot) if not name.startswith("_")}
    assert upward, "the engine reads the DH arm through its adapter"
    for caller, callee, name in upward:
        assert (caller, callee) == ("core", "aaria"), name
        assert name.startswith("aaria_pin.aaria.arm_run:"), name
        assert name.split(":")[1] in protocol, name


def test_the_trace_sees_a_call_back_up() -> None:
    """The check can fail: a core function that calls the CLI is seen as an upward call."""
    calls: list[tuple[str, str]] = []

    def profile(frame: FrameType, event: str, arg: Any) -> None:
        if event == "call" and frame.f_back is not None:
            callee = _layer(frame.f_globals.get("__name__", ""))
            caller = _layer(frame.f_back.f_globals.get("__name__", ""))
            if callee and caller:
                calls.append((caller, callee))

    from aaria_pin.cli import _app
    from aaria_pin.core import seeds

    namespace = {"__name__": seeds.__name__, "flag_names": _app.flag_names}
    exec("def up():\n    return flag_names(None)\n", namespace)
    sys.setprofile(profile)
    try:
        namespace["up"]()
    finally:
        sys.setprofile(None)
    assert ("core", "cli") in calls
