"""The compiled (numba) kernels: one decorator, a disk cache, a message while they compile.

Every kernel of the package is declared with :func:`kernel` (``numba.njit`` with
``cache=True``), so it is compiled once per install and loaded from numba's disk cache by later
processes. Where the cache lives is numba's choice, checked on this machine: next to the
module (``aaria_pin/core/__pycache__``) when that folder is writable, else numba's user-wide
cache (``~/.cache/numba/…``, or ``$NUMBA_CACHE_DIR`` when set). The fallback was verified with
a read-only copy of the package run by a root stripped of ``CAP_DAC_OVERRIDE`` (so the
permissions bite): the first run compiled into ``$HOME/.cache/numba`` and the second loaded from
it (5.2 s, then 2.0 s). That is what ``tests/core/test_compile_cache.py`` checks too, so the
package sets no cache folder of its own.

A first compile of the kernels takes about :data:`COMPILE_SECONDS` seconds, which used to pass
in silence. :func:`kernel` registers a listener on numba's ``"numba:compile"`` event (numba's
public event API, ``numba.core.event``), which numba broadcasts only after a cache miss, just
before it compiles: a load from the disk cache never raises it. So the message
(``aaria: compiling the kernels once (seconds: ...); later runs load them from <dir>``) goes to
stderr exactly when a compile really starts, at most once per process, and costs nothing on a
call that finds its compiled code in memory. Checking numba's index files beforehand was the
alternative; it would mean computing each call's type signature and reading numba's private
index format, and could still be wrong when the index is stale.

Start-up of the command line (:func:`light_start`): the first call of a cached kernel makes
numba load all of its implementation registries, and one of them (``numba.np.arraymath``)
imports ``scipy.linalg`` only to learn whether BLAS is there for ``np.dot`` inside compiled
code (``np.correlate``/``np.convolve`` of floats). None of our kernels uses BLAS, and that import
was 0.23 s of a 1.1 s ``aaria simulate`` (measured: first call of a cached kernel 0.37–0.46 s
with it, 0.12–0.13 s without). :func:`light_start`, called by the ``aaria`` command only, hides
the BLAS module from that one probe; numba then uses its own loop for such inner products in
that process. Library users keep numba's default.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any

__all__ = ["COMPILE_SECONDS", "compile_message", "kernel", "light_start"]

COMPILE_SECONDS = 3
"""Wall time of a first compile of every kernel on the project's machine [s]: the first
``aaria simulate`` with an empty cache took 3.9 s against 1.4 s warm (``benchmarks/bench_cli.py``;
5.2 s against 1.6–2.0 s on a busier machine)."""

_BLAS_PROBE = "scipy.linalg.cython_blas"
_state = {"light": False, "announced": False, "listening": False}


def light_start() -> None:
    """Make the numba start-up of this process light (the ``aaria`` command calls this).

    When numba is first loaded afterwards and ``scipy.linalg`` is not imported yet, numba's
    BLAS probe is skipped (see the module docstring): 0.23 s less for a command that runs a
    kernel, and our kernels do not use BLAS.
    """
    _state["light"] = True


def compile_message(cache_dir: str | None) -> str:
    """The one line printed on stderr while the kernels compile.

    Args:
        cache_dir: the folder numba caches the compiled code in (None when unknown)
    """
    where = cache_dir if cache_dir else "numba's cache"
    return (
        "aaria: compiling the kernels once (seconds: 3-5 for the IMUs', 10-15 more for a "
        "torque or closed-loop drive's); "
        f"later runs load them from {where}"
    )


def _load_numba() -> Any:
    """Import numba (once), lightly if :func:`light_start` was called, and listen for compiles."""
    light = _state["light"] and "numba.np.arraymath" not in sys.modules
    import numba

    if light and "scipy.linalg" not in sys.modules and _BLAS_PROBE not in sys.modules:
        sys.modules[_BLAS_PROBE] = None  # type: ignore[assignment]  # its import now fails
        try:
            import numba.np.arraymath  # the probe runs (and fails) here, once
        finally:
            del sys.modules[_BLAS_PROBE]
    if not _state["listening"]:
        from numba.core import event

        event.register("numba:compile", _compile_listener(event.Listener))
        _state["listening"] = True
    return numba


def _is_ours(dispatcher: Any) -> bool:
    """Whether a numba dispatcher is one of the package's kernels."""
    module = getattr(getattr(dispatcher, "py_func", None), "__module__", None) or ""
    return str(module).startswith("aaria_pin.")


def _compile_listener(base: type) -> Any:
    """A numba event listener: prints :func:`compile_message` once, as our first kernel compiles.

    ``base`` is ``numba.core.event.Listener`` (numba is imported only when a kernel is made).
    """

    class CompileListener(base):
        def on_start(self, event: Any) -> None:
            dispatcher = (event.data or {}).get("dispatcher")
            if _state["announced"] or not _is_ours(dispatcher):
                return
            _state["announced"] = True
            cache = getattr(dispatcher, "_cache", None)
            print(compile_message(getattr(cache, "cache_path", None)), file=sys.stderr)
            sys.stderr.flush()

        def on_end(self, event: Any) -> None:
            pass

    return CompileListener()


def kernel(function: Callable[..., Any] | None = None, *, exact: bool = False) -> Any:
    """``numba.njit(cache=True, fastmath=True, error_model="numpy")``: a cached kernel.

    The flags are those every kernel of the package has always been compiled with (the
    results are compared bit for bit with earlier versions), and importing numba through here
    registers the compile message (module docstring). ``@kernel(exact=True)`` compiles without
    ``fastmath``: IEEE arithmetic in the written order, no fused multiply-adds, no
    reassociation, so a kernel that replaces numpy array expressions gives their numbers bit
    for bit (the trajectory kernels, which replaced array code whose outputs the 0.1 fixtures
    hold).
    """
    numba = _load_numba()
    if function is None:
        return lambda inner: numba.njit(cache=True, fastmath=not exact, error_model="numpy")(inner)
    return numba.njit(cache=True, fastmath=not exact, error_model="numpy")(function)
