"""The compiled kernels: cached on disk once, and a first compile says so on stderr.

Each test runs fresh Python processes against an empty numba cache, so it compiles one small
kernel (``free_flyer_state``, about a second) and then loads it.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from aaria_pin.core._compile import compile_message

ROOT = Path(__file__).resolve().parents[2]
MESSAGE = "aaria: compiling the kernels once"

# A foreign numba function compiles first (it must not trigger the message), then one kernel of
# ours runs on an identity base at rest, whose free-flyer state is known: q = [p, 0, 0, 0, 1].
SCRIPT = """
import json
import sys
import numpy as np
from aaria_pin.core._kinematics_kernel import free_flyer_state
import numba

@numba.njit
def foreign(x):
    return x + 1.0

foreign(1.0)
print("FOREIGN-DONE", file=sys.stderr, flush=True)
T = 3
R = np.tile(np.eye(3), (T, 1, 1))
p = np.arange(T * 3, dtype=float).reshape(T, 3)
z = np.zeros((T, 3))
q, v, a = np.zeros((T, 7)), np.ones((T, 6)), np.ones((T, 6))
free_flyer_state(R, p, z, z, z, z, q, v, a)
print(json.dumps([q.tolist(), v.tolist(), a.tolist()]))
"""


def _run(env: dict[str, str], *prefix: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [*prefix, sys.executable, "-c", SCRIPT],
        capture_output=True,
        text=True,
        env=env,
        cwd=env.get("HOME", str(ROOT)),
        check=True,
    )


def _clean_env(**extra: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "XDG_CACHE_HOME")}
    env.update(extra)
    return env


def _check_state(stdout: str) -> None:
    """The identity base at rest: q = [p, 0, 0, 0, 1], zero body velocity and acceleration."""
    q, v, a = json.loads(stdout)
    assert q == [[3.0 * t, 3.0 * t + 1, 3.0 * t + 2, 0.0, 0.0, 0.0, 1.0] for t in range(3)]
    assert v == [[0.0] * 6] * 3
    assert a == [[0.0] * 6] * 3


def test_first_compile_says_so_and_the_next_process_loads_from_the_cache(tmp_path: Path) -> None:
    cache = tmp_path / "numba-cache"
    env = _clean_env(NUMBA_CACHE_DIR=str(cache))
    first = _run(env)
    before, _, after = first.stderr.partition("FOREIGN-DONE")
    assert MESSAGE not in before  # a foreign function compiling says nothing
    lines = [line for line in after.splitlines() if MESSAGE in line]
    assert len(lines) == 1, first.stderr
    assert str(cache) in lines[0]
    _check_state(first.stdout)
    assert any("free_flyer_state" in path.name for path in cache.rglob("*.nbi"))

    second = _run(env)
    assert MESSAGE not in second.stderr, second.stderr
    _check_state(second.stdout)


def test_the_message_names_the_cache_folder() -> None:
    text = compile_message("/some/cache")
    assert text.startswith(MESSAGE)
    assert text.endswith("later runs load them from /some/cache")
    assert "\n" not in text


@pytest.mark.skipif(
    not hasattr(os, "geteuid") or os.geteuid() != 0 or shutil.which("setpriv") is None,
    reason="needs root and setpriv to make a folder read-only for this process",
)
def test_a_read_only_package_caches_in_the_user_folder(tmp_path: Path) -> None:
    """numba's own fallback: a read-only package folder caches under ``~/.cache/numba``."""
    package = tmp_path / "site" / "aaria_pin"
    shutil.copytree(
        ROOT / "aaria_pin", package, ignore=shutil.ignore_patterns("__pycache__", "*.nb[ic]")
    )
    for folder, _, files in os.walk(package):
        os.chmod(folder, 0o555)
        for name in files:
            os.chmod(Path(folder) / name, 0o444)
    home = tmp_path / "home"
    home.mkdir()
    env = _clean_env(PYTHONPATH=str(package.parent), HOME=str(home))
    # root without CAP_DAC_OVERRIDE: the permissions of the copy now apply to this process
    setpriv = ("setpriv", "--bounding-set=-dac_override,-dac_read_search,-fowner")
    try:
        first = _run(env, *setpriv)
        user_cache = home / ".cache" / "numba"
        assert MESSAGE in first.stderr and str(user_cache) in first.stderr, first.stderr
        assert any(user_cache.rglob("*.nbi"))
        assert not any(package.rglob("*.nbi"))
        second = _run(env, *setpriv)
        assert MESSAGE not in second.stderr, second.stderr
        _check_state(second.stdout)
    finally:
        for folder, _, _ in os.walk(package):
            os.chmod(folder, 0o755)
