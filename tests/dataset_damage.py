"""Real data sets to damage in tests: a small one made by the tool, and a chunk's bytes flipped."""

from __future__ import annotations

from pathlib import Path

import h5py
from conftest import run_cli


def small_dataset(path: Path) -> Path:
    """``aaria dataset -n 3 --duration 0.2 --rate 100 -o PATH`` (21 samples a run)."""
    status, _, err = run_cli(
        "dataset", "-n", "3", "--duration", "0.2", "--rate", "100", "-o", str(path), "--quiet"
    )
    assert status == 0, err
    return path


def flip_chunk(path: Path, name: str, run: int) -> None:
    """Overwrite 8 bytes in the middle of run ``run``'s (first) stored chunk of ``name``."""
    with h5py.File(path, "r") as handle:
        dataset = handle[name]
        info = dataset.id.get_chunk_info_by_coord((run,) + (0,) * (dataset.ndim - 1))
    with path.open("r+b") as stream:
        stream.seek(info.byte_offset + info.size // 2)
        data = stream.read(8)
        stream.seek(info.byte_offset + info.size // 2)
        stream.write(bytes(b ^ 0xFF for b in data))
