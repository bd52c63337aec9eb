"""Bytes flipped in HDF5's own metadata (object headers, B-trees, heaps) of a run file, a data set.

HDF5 raises RuntimeError for some damaged metadata ("Link iteration failed (incorrect metadata
checksum ...)", "Error iterating over attributes"): every read through
:func:`~aaria_pin.files.source.open_record` returns or raises one-line InputFileError. Each read
runs in a forked child, as a few flips crash libhdf5 itself (a segmentation fault in
``H5Literate``): those are counted apart, not as failures of ours.
"""

from __future__ import annotations

import faulthandler
import os
import signal
from pathlib import Path

import pytest
from click.testing import CliRunner
from dataset_damage import small_dataset

from aaria_pin.cli import main
from aaria_pin.errors import AariaError, InputFileError
from aaria_pin.files.source import open_record

SPAN = 16_384
STEP = 211

pytestmark = pytest.mark.skipif(not hasattr(os, "fork"), reason="needs fork")


def _read_in_child(path: Path, run: int | None) -> str:
    """How a read of ``path`` ended: "ok", "error", "signal", or the unexpected exception."""
    reader, writer = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: read, report, leave without pytest's clean-up
        os.close(reader)
        faulthandler.disable()  # libhdf5's own crash: no dump of it
        try:
            open_record(path, run=run)
            outcome = "ok"
        except InputFileError as exc:
            outcome = "error" if "\n" not in str(exc) else f"two lines: {exc}"
        except AariaError as exc:  # "run is for a data set": its format mark was flipped
            outcome = "error" if "\n" not in str(exc) and "a run file" in str(exc) else str(exc)
        except BaseException as exc:
            outcome = f"{type(exc).__name__}: {exc}"
        os.write(writer, outcome.encode()[:4000])
        os._exit(0)
    os.close(writer)
    with os.fdopen(reader, "rb") as stream:
        outcome = stream.read().decode()
    _, status = os.waitpid(pid, 0)
    if os.WIFSIGNALED(status) and os.WTERMSIG(status) in (signal.SIGSEGV, signal.SIGABRT):
        return "signal"
    return outcome


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    folder = tmp_path_factory.mktemp("metadata")
    result = CliRunner().invoke(
        main,
        [
            *("simulate", "--preset", "aaria-fig2", "--duration", "0.2", "--rate", "100"),
            *("-o", str(folder / "run.h5")),
        ],
    )
    assert result.exit_code == 0, result.output
    return {"run": folder / "run.h5", "dataset": small_dataset(folder / "ds.h5")}


@pytest.mark.parametrize("kind", ["run", "dataset"])
def test_flipped_metadata_is_an_input_file_error(
    files: dict[str, Path], tmp_path: Path, kind: str
) -> None:
    original = files[kind].read_bytes()
    run = 0 if kind == "dataset" else None
    path = tmp_path / "flipped.h5"
    outcomes: dict[str, list[int]] = {}
    for offset in range(0, min(SPAN, len(original) - 4), STEP):
        data = bytearray(original)
        data[offset : offset + 4] = bytes(b ^ 0xFF for b in data[offset : offset + 4])
        path.write_bytes(bytes(data))
        outcome = _read_in_child(path, run)
        outcomes.setdefault(outcome, []).append(offset)
    unexpected = {k: v for k, v in outcomes.items() if k not in ("ok", "error", "signal")}
    assert not unexpected, unexpected
    assert len(outcomes.get("error", [])) > 10  # the sweep did reach damage
